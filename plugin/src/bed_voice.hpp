// One source slot's Ambisonic bed renderer and its hand-over between the
// control thread and the audio thread, as the World hands over renderers
// (world.hpp): the control thread makes a BedUnit (a BedRenderer for the
// bed's order with the decoder of the world's HRTF set, and its buffers) and
// offers it through an atomic pointer; the audio thread adopts it at a block
// start, and hands the one it replaced back through another atomic pointer
// for the control thread to free.
//
// A unit of the order already playing (a new HRTF set) is faded in as the
// world's renderer is (audio::CrossfadeSwitch: both on the same input for
// 512 frames, then a 512-frame raised cosine); a unit of another order (a new
// buffer) replaces the old one at once. Nothing on the audio thread
// allocates, frees or locks.
#pragma once

#include <atomic>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "earshot/audio/ambisonics/bed_renderer.hpp"
#include "earshot/audio/crossfade_switch.hpp"

namespace earshot::plugin {

/// A BedRenderer and the block buffers around it.
struct BedUnit {
  BedUnit(const ambisonics::DecoderFilters& filters, std::size_t block)
      : bed(filters, block), input(filters.channels() * block, 0.0f), left(block, 0.0f), right(block, 0.0f) {}
  ambisonics::BedRenderer bed;
  std::vector<float> input;  ///< channels x block planar, ambiX
  std::vector<float> left, right;
  [[nodiscard]] int order() const { return bed.order(); }
};

class BedVoice {
 public:
  BedVoice() = default;
  ~BedVoice() {
    std::unique_ptr<BedUnit> in(incoming_.exchange(nullptr));
    std::unique_ptr<BedUnit> out(outgoing_.exchange(nullptr));
  }
  BedVoice(const BedVoice&) = delete;
  BedVoice& operator=(const BedVoice&) = delete;

  // ---- control thread ----
  /// Offers `unit` to the audio thread (one not adopted yet is replaced and freed here).
  void offer(std::unique_ptr<BedUnit> unit) {
    reclaim();
    std::unique_ptr<BedUnit> unused(incoming_.exchange(unit.release(), std::memory_order_acq_rel));
  }
  /// Frees what the audio thread handed back.
  void reclaim() { std::unique_ptr<BedUnit> done(outgoing_.exchange(nullptr, std::memory_order_acquire)); }
  /// The order of the unit last offered (0: none): what the control side expects to play.
  [[nodiscard]] int offered_order() const { return offered_order_; }
  void set_offered_order(int order) { offered_order_ = order; }

  // ---- audio thread ----
  /// At a block start: takes an offered unit. `nothing_heard_yet`: no fade.
  void adopt(bool nothing_heard_yet) {
    hand_back();
    // One switch at a time, and none while a finished unit waits to go back:
    // then the switch's own slot for finished units is empty (nothing is
    // ever freed here).
    if (units_.switching() || retired_) return;
    BedUnit* next = incoming_.exchange(nullptr, std::memory_order_acq_rel);
    if (!next) return;
    const bool fade = has_current_ && !nothing_heard_yet && units_.current().order() == next->order();
    (void)units_.switch_to(std::unique_ptr<BedUnit>(next));  // null: no switch was under way
    has_current_ = true;
    if (!fade) units_.cut();  // another order, or nothing to fade from: at once
    hand_back();
  }
  [[nodiscard]] BedUnit* current() { return has_current_ ? &units_.current() : nullptr; }
  [[nodiscard]] BedUnit* fading() { return units_.fading(); }
  /// Blends a switch's block (CrossfadeSwitch::blend) and hands a unit that
  /// has faded out back.
  void blend(std::span<float> left, std::span<float> right, std::span<const float> old_left,
             std::span<const float> old_right) {
    units_.blend(left, right, old_left, old_right);
    hand_back();
  }

 private:
  void hand_back() {
    if (!retired_) retired_ = units_.finished();
    if (retired_ && !outgoing_.load(std::memory_order_relaxed))
      outgoing_.store(retired_.release(), std::memory_order_release);
  }

  std::atomic<BedUnit*> incoming_{nullptr};  // control -> audio
  std::atomic<BedUnit*> outgoing_{nullptr};  // audio -> control, to free
  audio::CrossfadeSwitch<BedUnit> units_;    // audio side
  std::unique_ptr<BedUnit> retired_;         // audio side: waiting for outgoing_ to be free
  bool has_current_ = false;                 // audio side
  int offered_order_ = 0;                    // control side
};

}  // namespace earshot::plugin
