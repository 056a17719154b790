// Offline rendering of a scene to a WAV file through the plugin's C API:
// deterministic (the same inputs give the same bytes), block by block.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "earshot/host/wav_writer.hpp"
#include "earshot/scenes/scene.hpp"

namespace earshot::host {

struct RenderOptions {
  std::filesystem::path out;
  std::optional<double> duration_s;   ///< overrides the scene's
  std::optional<double> sample_rate;  ///< overrides the scene's
  std::size_t block = 128;
  std::filesystem::path hrtf;         ///< empty: the default MIT KEMAR set
  std::optional<std::filesystem::path> pose_track;  ///< overrides the scene's
  WavFormat format = WavFormat::float32;
  /// The renderer tier, overriding the scene's: "direct" or "ambisonic:N".
  std::optional<std::string> quality;
  /// The binaural decoder of beds and of the Ambisonic tier: "magls" or "ls".
  std::string decoder = "magls";
  /// Called now and then with the fraction done (0..1).
  std::function<void(double)> progress;
  /// Asked before each block; true ends the render there (e.g. on SIGTERM):
  /// the WAV is closed with the frames rendered so far, its header complete.
  std::function<bool()> stop;
};

struct RenderStats {
  std::size_t frames = 0;  ///< frames in the WAV
  double peak = 0.0;       ///< largest absolute sample written
  bool stopped = false;    ///< `stop` ended the render before the duration
};

/// Throws earshot::InputError for bad input (scene, HRTF, pose track, output).
RenderStats render_scene(const scenes::Scene& scene, const RenderOptions& opt);

}  // namespace earshot::host
