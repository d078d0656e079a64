// Subcommands of the masq CLI. Each registers its options and returns the action to run.
#pragma once
#include <CLI/CLI.hpp>
#include <functional>

namespace masq::cli {
using Action = std::function<int()>;
Action add_info(CLI::App& app);
Action add_render(CLI::App& app);
Action add_bench(CLI::App& app);
Action add_stress(CLI::App& app);
Action add_report(CLI::App& app);
} // namespace masq::cli
