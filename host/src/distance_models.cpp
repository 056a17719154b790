#include "earshot/host/distance_models.hpp"

namespace earshot::host {

ESenum es_distance_model(audio::DistanceModel m) {
  using M = audio::DistanceModel;
  switch (m) {
    case M::none: return ES_NONE;
    case M::inverse: return ES_INVERSE_DISTANCE;
    case M::inverse_clamped: return ES_INVERSE_DISTANCE_CLAMPED;
    case M::linear: return ES_LINEAR_DISTANCE;
    case M::linear_clamped: return ES_LINEAR_DISTANCE_CLAMPED;
    case M::exponent: return ES_EXPONENT_DISTANCE;
    case M::exponent_clamped: return ES_EXPONENT_DISTANCE_CLAMPED;
  }
  return ES_INVERSE_DISTANCE_CLAMPED;
}

int distance_model_index(audio::DistanceModel m) {
  for (std::size_t i = 0; i < kDistanceModels.size(); ++i)
    if (kDistanceModels[i].model == m) return static_cast<int>(i);
  return 2;  // inverse clamped, OpenAL's default
}

}  // namespace earshot::host
