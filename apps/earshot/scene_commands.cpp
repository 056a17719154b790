#include "scene_commands.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <memory>
#include <string>

#include "earshot/errors.hpp"
#include "earshot/scenes/presets.hpp"
#include "earshot/scenes/scene.hpp"

namespace earshot::app {

namespace {
struct PathsArgs {
  std::string scene, out;
  double step = 0.05, duration = -1;
};
}  // namespace

void add_scene_commands(CLI::App& scene) {
  auto* list = scene.add_subcommand("list", "List the shipped preset scenes with their descriptions");
  list->callback([] {
    for (const auto& name : scenes::preset_names()) {
      const auto sc = scenes::load_scene(scenes::resolve_scene_argument(name));
      std::printf("%-16s %s\n", name.c_str(), sc.description.c_str());
    }
  });
  auto a = std::make_shared<PathsArgs>();
  auto* cmd = scene.add_subcommand(
      "paths", "Write where every source is over time as CSV (t,source,x,y,z; metres, audio world frame)");
  cmd->add_option("--scene,-s", a->scene, "Scene JSON file or a shipped preset's name")->required();
  cmd->add_option("--out,-o", a->out, "CSV file to write")->required();
  cmd->add_option("--step", a->step, "Seconds between samples")->capture_default_str();
  cmd->add_option("--duration", a->duration, "Seconds (default: the scene's duration_s)");
  cmd->callback([a] {
    if (!(a->step >= 1e-3 && a->step <= 60)) throw InputError::at("--step", 0, "", "must be 0.001 to 60 s");
    const auto sc = scenes::load_scene(scenes::resolve_scene_argument(a->scene));
    const double duration = a->duration >= 0 ? a->duration : sc.duration_s;
    std::ofstream out(a->out);
    if (!out) throw InputError::at(a->out, 0, "", "cannot write");
    out << "t,source,x,y,z\n";
    const auto steps = static_cast<long>(std::floor(duration / a->step + 1e-9));
    out << std::fixed << std::setprecision(4);
    for (long k = 0; k <= steps; ++k) {
      const double t = static_cast<double>(k) * a->step;
      for (const auto& src : sc.sources) {
        const auto p = scenes::source_position(src, t);
        // Names are quoted CSV fields: they may hold commas.
        std::string name;
        for (const char c : src.name) {
          if (c == '"') name += '"';  // a quote inside a quoted field is doubled
          name += c;
        }
        out << t << ",\"" << name << "\"," << p[0] << ',' << p[1] << ',' << p[2] << '\n';
      }
    }
    if (!out.flush()) throw InputError::at(a->out, 0, "", "write failed");
    std::printf("wrote %s: %ld samples of %zu sources\n", a->out.c_str(), steps + 1, sc.sources.size());
  });
}

}  // namespace earshot::app
