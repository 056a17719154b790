// Fuzzes the SOFA loader the plugin uses (HrtfSet::load: signature check,
// libmysofa, the convention checks, resampling, the onset split, the
// triangulation): a loaded set or InputError, nothing else. libmysofa reads
// files by path, so each input goes through a file of this process's own.
// Seeds: small sets written by tests/fixtures/make_sofa.py (see CMakeLists).
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "earshot/errors.hpp"
#include "earshot/hrtf/hrtf_set.hpp"

namespace {
/// This process's input file, removed when the process ends.
struct InputFile {
  std::string path = "/tmp/earshot_fuzz_sofa_" + std::to_string(getpid()) + ".sofa";
  ~InputFile() { std::remove(path.c_str()); }
};
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const InputFile input;
  const std::string& path = input.path;
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  try {
    const auto set = earshot::hrtf::HrtfSet::load(path, 48000.0);
    if (set.measurement_count() < 4 || set.filter_length() == 0) std::abort();
  } catch (const earshot::InputError&) {
  }
  return 0;
}
