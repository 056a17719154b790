// `earshot render`: a Scene JSON to a WAV file, offline and deterministic.
#pragma once

#include <CLI/CLI.hpp>

namespace earshot::app {
void add_render_command(CLI::App& app);
}
