#pragma once

#include <CLI/CLI.hpp>

namespace earshot::app {

/// `earshot demo`: a scene heard through a tracked head.
void add_demo_command(CLI::App& app);

}  // namespace earshot::app
