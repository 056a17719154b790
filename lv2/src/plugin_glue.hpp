// The C entry points of an LV2 plugin, written once for every plugin of the
// bundle. LV2 calls plain functions with an LV2_Handle; PluginGlue<P>'s
// forward them to the members of the plugin class P:
//
//   P(double rate, const LV2_Feature* const* features, Args...)   may throw
//   void connect(std::uint32_t port, void* data)
//   void activate()
//   void run(std::uint32_t frames)
//   LV2_Worker_Status work(respond, handle, size, data)             worker thread
//   LV2_Worker_Status work_response(size, data)
//   LV2_State_Status save(store, handle, features)
//   LV2_State_Status restore(retrieve, handle, features)
//
// A constructor that throws makes instantiate() return NULL (what LV2 asks
// for) after telling the host's log why, when the host has one.
#pragma once

#include <lv2/core/lv2.h>
#include <lv2/log/log.h>
#include <lv2/log/logger.h>
#include <lv2/state/state.h>
#include <lv2/worker/worker.h>

#include <cstdint>
#include <exception>
#include <memory>
#include <string_view>

#include "features.hpp"

namespace earshot::lv2 {

template <class P>
struct PluginGlue {
  static P* self(LV2_Handle h) { return static_cast<P*>(h); }

  /// Makes a P from the host's rate and features (and `args`); `name` heads
  /// the log line when that fails.
  template <class... Args>
  static LV2_Handle make(const char* name, double rate, const LV2_Feature* const* features, Args... args) {
    try {
      return std::make_unique<P>(rate, features, args...).release();  // the host's until cleanup
    } catch (const std::exception& e) {
      if (auto* log = static_cast<LV2_Log_Log*>(const_cast<void*>(feature_data(features, LV2_LOG__log)))) {
        LV2_Log_Logger logger{};
        lv2_log_logger_init(&logger, nullptr, log);
        lv2_log_error(&logger, "%s: %s\n", name, e.what());
      }
      return nullptr;
    }
  }

  static void connect_port(LV2_Handle h, std::uint32_t port, void* data) { self(h)->connect(port, data); }
  static void activate(LV2_Handle h) { self(h)->activate(); }
  static void run(LV2_Handle h, std::uint32_t frames) { self(h)->run(frames); }
  static void deactivate(LV2_Handle) {}
  static void cleanup(LV2_Handle h) { std::unique_ptr<P> owned(self(h)); }

  static LV2_Worker_Status work(LV2_Handle h, LV2_Worker_Respond_Function respond, LV2_Worker_Respond_Handle handle,
                                std::uint32_t size, const void* data) {
    return self(h)->work(respond, handle, size, data);
  }
  static LV2_Worker_Status work_response(LV2_Handle h, std::uint32_t size, const void* data) {
    return self(h)->work_response(size, data);
  }
  static LV2_State_Status save(LV2_Handle h, LV2_State_Store_Function store, LV2_State_Handle handle, std::uint32_t,
                               const LV2_Feature* const* features) {
    return self(h)->save(store, handle, features);
  }
  static LV2_State_Status restore(LV2_Handle h, LV2_State_Retrieve_Function retrieve, LV2_State_Handle handle,
                                  std::uint32_t, const LV2_Feature* const* features) {
    return self(h)->restore(retrieve, handle, features);
  }

  /// The worker and state interfaces.
  static const void* extension_data(const char* uri) {
    static const LV2_Worker_Interface worker{work, work_response, nullptr};
    static const LV2_State_Interface state{save, restore};
    if (std::string_view(uri) == LV2_WORKER__interface) return &worker;
    if (std::string_view(uri) == LV2_STATE__interface) return &state;
    return nullptr;
  }

  /// A descriptor for `uri` whose instantiate is `instantiate`.
  static constexpr LV2_Descriptor descriptor(const char* uri, LV2_Handle (*instantiate)(const LV2_Descriptor*, double,
                                                                                       const char*,
                                                                                       const LV2_Feature* const*)) {
    return {uri, instantiate, connect_port, activate, run, deactivate, cleanup, extension_data};
  }
};

}  // namespace earshot::lv2
