// A look at a SOFA file's HDF5 object headers before libmysofa reads it.
//
// libmysofa (1.3) reads every attribute element by element, looping over
// the dimensions its dataspace message declares, without checking them
// against the file: a flipped byte there (found by fuzz_sofa) makes it seek
// past the end of the file billions of times (minutes in one load), and a
// dataset's dimensions size the buffer it allocates. This walks the object
// headers the way libmysofa does (every "OHDR" in the file, the "OCHK"
// continuations they name) and refuses, before libmysofa runs, any
// dataspace that declares more elements than a SOFA file can sensibly
// hold. It reads nothing else and decides nothing about validity: what it
// passes, libmysofa still checks.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace earshot::hrtf::detail {

/// Elements an attribute may declare (SOFA attributes are strings, a
/// dimension list of up to 4 references, or a short list of references).
inline constexpr std::uint64_t kMaxAttributeElements = 4096;

/// Why `file` (the whole SOFA file) must not go to libmysofa, naming the
/// header and its dimensions; empty when nothing is wrong. `max_dataset`:
/// the most values a dataset may declare.
[[nodiscard]] std::string sofa_header_problem(std::span<const std::uint8_t> file, std::uint64_t max_dataset);

}  // namespace earshot::hrtf::detail
