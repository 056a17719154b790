// earshot-openal-run [--tracker SPEC] [--place stereo|all|none] [--recenter-after S] [--] PROGRAM ARGS...
// Runs PROGRAM with libearshot_openal_preload.so preloaded (docs/OPENAL_RUN.md):
// finds the library next to this executable (build tree) or in the install
// lib directory, prepends it to LD_PRELOAD, passes the options on in
// EARSHOT_OPENAL_* variables and execvp's the program (exit 127 when it is
// not found, 126 when it cannot be run, like a shell).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "earshot/errors.hpp"
#include "earshot/tracker/live/source_spec.hpp"

namespace fs = std::filesystem;

namespace {

constexpr const char* kLibrary = "libearshot_openal_preload.so";

// The shim: beside the executable (build tree), then EARSHOT_PRELOAD_RELDIR
// from it (bin/ -> lib/ when installed).
std::optional<fs::path> find_shim() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  if (ec) return std::nullopt;
  for (const fs::path& candidate : {exe.parent_path() / kLibrary,
                                    exe.parent_path() / EARSHOT_PRELOAD_RELDIR / kLibrary}) {
    if (fs::is_regular_file(candidate, ec)) return fs::weakly_canonical(candidate, ec);
  }
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Head tracking for an unmodified OpenAL Soft program: runs PROGRAM with Earshot's preload shim,\n"
               "which turns and moves the program's OpenAL listener by the tracked head.",
               "earshot-openal-run"};
  std::string spec = "wiimote";
  std::string place = "stereo";
  double recenter_after = 0;
  bool verbose = false;
  app.add_option("--tracker", spec, std::string("head tracker: ") + std::string(earshot::tracker::kSourceSpecs))
      ->capture_default_str();
  app.add_option("--place", place,
                 "stereo: a stereo source's two channels become speakers at +-30 degrees in the room "
                 "(AL_STEREO_ANGLES turned against the head's yaw); all: also mono sources playing at the "
                 "listener move 1 m ahead in the room; none: sources as OpenAL plays them")
      ->check(CLI::IsMember({"stereo", "all", "none"}))
      ->capture_default_str();
  app.add_option("--recenter-after", recenter_after, "recenter the tracker once, S seconds after it starts")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--verbose", verbose, "say on stderr what the shim does (contexts, stereo sources)");
  app.prefix_command();
  app.footer(
      "Examples:\n"
      "  earshot-openal-run -- mpg123 -o openal music.mp3\n"
      "  earshot-openal-run --tracker osc:9000 -- gst-launch-1.0 audiotestsrc ! openalsink\n"
      "  earshot-openal-run --tracker sim python3 game.py\n"
      "OpenAL Soft must render with HRTF (alsoft.conf: hrtf = true) for the head to be heard.");
  CLI11_PARSE(app, argc, argv);

  std::vector<std::string> command = app.remaining();
  if (!command.empty() && command.front() == "--") command.erase(command.begin());
  if (command.empty()) {
    std::cerr << "earshot-openal-run: no PROGRAM given (see --help)\n";
    return 2;
  }
  try {
    (void)earshot::tracker::parse_source_spec(spec, "--tracker");
  } catch (const std::exception& e) {
    std::cerr << "earshot-openal-run: " << e.what() << "\n";
    return 2;
  }
  const auto shim = find_shim();
  if (!shim) {
    std::cerr << "earshot-openal-run: cannot find " << kLibrary << " next to this program or in its lib directory\n";
    return 1;
  }
  std::string preload = shim->string();
  if (const char* old = std::getenv("LD_PRELOAD"); old && *old) preload += std::string(" ") + old;
  setenv("LD_PRELOAD", preload.c_str(), 1);
  setenv("EARSHOT_OPENAL_TRACKER", spec.c_str(), 1);
  setenv("EARSHOT_OPENAL_PLACE", place.c_str(), 1);
  if (recenter_after > 0)
    setenv("EARSHOT_OPENAL_RECENTER_AFTER", std::to_string(recenter_after).c_str(), 1);
  else
    unsetenv("EARSHOT_OPENAL_RECENTER_AFTER");
  if (verbose) setenv("EARSHOT_OPENAL_RUN_VERBOSE", "1", 1);

  std::vector<char*> args;
  for (std::string& a : command) args.push_back(a.data());
  args.push_back(nullptr);
  execvp(args[0], args.data());
  const int err = errno;
  std::cerr << "earshot-openal-run: " << command.front() << ": "
            << (err == ENOENT ? "command not found" : std::strerror(err)) << "\n";
  return err == ENOENT ? 127 : 126;
}
