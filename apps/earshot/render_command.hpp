// `earshot render`: a Scene JSON (or an Ambisonic file, --ambix) to a WAV
// file, offline and deterministic.
// SIGINT, SIGTERM or SIGHUP stop it at the next block: the WAV is kept, a
// valid file (header final) with the frames rendered so far, and the command
// says so and exits with status 1, as the file is not the one asked for.
#pragma once

#include <CLI/CLI.hpp>

namespace earshot::app {
void add_render_command(CLI::App& app);
}
