// The tracked head as a host hears it: read once per audio block (or per
// pose, where a host applies poses as they come), carried on to when that
// audio is heard, and placed on the listener the host put in its world.
// Every host reads the head this way: the C API's World, the LV2 plugins,
// the OpenAL bridge and the preload shim.
//
//   tracker thread --publish--> PoseSlot --HeadReader::read--> the head,
//   predicted to when the block is heard --compose(listener, head)--> the
//   pose the renderer (or OpenAL's listener) is given.
//
// Real-time safe: no allocation, lock, I/O or system call (steady_clock is
// read through the vDSO).
#pragma once

#include "earshot/head_pose.hpp"
#include "earshot/pose_slot.hpp"

namespace earshot::head {

/// Seconds on std::chrono::steady_clock: the clock of HeadPose::steady_s,
/// shared by the tracker thread and the audio thread.
[[nodiscard]] double steady_now_s();

/// When the audio shaped by a read is heard, and whether to predict to then.
struct HeadTiming {
  bool predict = true;  ///< carry the pose on at the tracker's velocities
  /// Seconds from the read to when its audio reaches the ear: a block plus
  /// the output's latency (the host's, the device's, a plugin's own FIFO).
  double lead_s = 0.0;
};

/// `p` as heard at steady-clock time `now_s` + timing.lead_s: carried on
/// there when timing.predict (extrapolate in head_pose.hpp: a tracking pose
/// with its filter's velocities, at most kMaxHeadPredictionS ahead; other
/// states as they are), else `p` itself. For hosts handed poses as they are
/// published (the preload shim); HeadReader does this for slot readers.
[[nodiscard]] HeadPose heard(const HeadPose& p, const HeadTiming& timing, double now_s);

/// Reads one tracker's slot for one consumer.
class HeadReader {
 public:
  /// The newest pose in `slot` (one attempt, never waiting: while the writer
  /// is mid-publication, or before its first pose, the last one read), as
  /// heard (above) now.
  [[nodiscard]] HeadPose read(const PoseSlot& slot, const HeadTiming& timing) {
    return read_at(slot, timing, steady_now_s());
  }
  /// As read, at steady-clock time `now_s` (tests).
  [[nodiscard]] HeadPose read_at(const PoseSlot& slot, const HeadTiming& timing, double now_s);

  /// The last pose read from the slot, before prediction.
  [[nodiscard]] const HeadPose& last() const { return last_; }
  /// Forgets it (a tracker detached or replaced): straight ahead again.
  void reset() { last_ = HeadPose{}; }

 private:
  HeadPose last_{};
};

/// The pose a head is heard from: the tracked `head` (its pose relative to
/// the listener: where the head moved and turned since recenter) placed on
/// the `listener` a host put in its world, p + P h and P H (position and
/// orientation; the rest of the result is `head`'s). A non-finite head
/// leaves the listener as it is.
[[nodiscard]] HeadPose compose(const HeadPose& listener, const HeadPose& head);

}  // namespace earshot::head
