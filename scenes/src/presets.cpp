#include "earshot/scenes/presets.hpp"

#include <algorithm>

#include "earshot/errors.hpp"

namespace earshot::scenes {
namespace fs = std::filesystem;

std::vector<fs::path> preset_dirs() {
  std::vector<fs::path> dirs;
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);  // Linux: the running executable
  if (!ec) dirs.push_back(exe.parent_path().parent_path() / "share" / "earshot" / "scenes");
  dirs.emplace_back(EARSHOT_PRESETS_SOURCE_DIR);
  std::erase_if(dirs, [](const fs::path& d) {
    std::error_code e;
    return !fs::is_directory(d, e);
  });
  return dirs;
}

std::vector<std::string> preset_names() {
  std::vector<std::string> names;
  for (const auto& d : preset_dirs()) {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(d, ec))
      if (e.path().extension() == ".json") names.push_back(e.path().stem().string());
  }
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}

fs::path resolve_scene_argument(std::string_view arg) {
  const fs::path p(arg);
  std::error_code ec;
  const bool bare = !arg.empty() && arg.find('/') == std::string_view::npos && p.extension() != ".json";
  if (!bare || fs::exists(p, ec)) return p;
  for (const auto& d : preset_dirs())
    if (fs::is_regular_file(d / (std::string(arg) + ".json"), ec)) return d / (std::string(arg) + ".json");
  std::string list;
  for (const auto& n : preset_names()) list += (list.empty() ? "" : ", ") + n;
  throw InputError::at(arg, 0, "", "no such scene file or preset (presets: " + (list.empty() ? "none found" : list) +
                                       ")");
}

}  // namespace earshot::scenes
