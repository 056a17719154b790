#include "earshot/head/head_reader.hpp"

#include <chrono>

namespace earshot::head {

double steady_now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

HeadPose heard(const HeadPose& p, const HeadTiming& timing, double now_s) {
  return timing.predict ? extrapolate(p, now_s + timing.lead_s) : p;
}

HeadPose HeadReader::read_at(const PoseSlot& slot, const HeadTiming& timing, double now_s) {
  if (auto p = slot.try_load()) last_ = *p;
  return heard(last_, timing, now_s);
}

HeadPose compose(const HeadPose& listener, const HeadPose& head) {
  HeadPose out = head;
  if (!head.finite()) {
    out.position = listener.position;
    out.orientation = listener.orientation;
    return out;
  }
  const Vec3 offset = rotate(listener.orientation, head.position);
  for (int i = 0; i < 3; ++i) out.position[i] = listener.position[i] + offset[i];
  out.orientation = multiply(listener.orientation, head.orientation);
  return out;
}

}  // namespace earshot::head
