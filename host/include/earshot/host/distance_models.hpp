// The distance models of a Scene (audio::DistanceModel) as the plugin names
// them (ES_INVERSE_DISTANCE_CLAMPED, ...), and as people read them.
#pragma once

#include <array>

#include "earshot/audio/distance_model.hpp"
#include "earshot/earshot.h"

namespace earshot::host {

/// The plugin's ES_*_DISTANCE* value of a model.
[[nodiscard]] ESenum es_distance_model(audio::DistanceModel m);

struct DistanceModelName {
  audio::DistanceModel model;
  const char* name;  ///< for people, e.g. "inverse clamped"
};

/// Every model, in the order of audio::DistanceModel (pickers index it).
inline constexpr std::array<DistanceModelName, 7> kDistanceModels{{
    {audio::DistanceModel::none, "none"},
    {audio::DistanceModel::inverse, "inverse"},
    {audio::DistanceModel::inverse_clamped, "inverse clamped"},
    {audio::DistanceModel::linear, "linear"},
    {audio::DistanceModel::linear_clamped, "linear clamped"},
    {audio::DistanceModel::exponent, "exponent"},
    {audio::DistanceModel::exponent_clamped, "exponent clamped"},
}};

/// The index of `m` in kDistanceModels.
[[nodiscard]] int distance_model_index(audio::DistanceModel m);

}  // namespace earshot::host
