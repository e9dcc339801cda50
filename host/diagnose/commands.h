// `wetdem diagnose` and `wetdem twin` on the CLI (registered by main.cpp; the logic is in this folder). The
// command interface is the study layer's (study/commands.h): the diagnosis sits on top of it.
#pragma once

#include <memory>

#include "study/commands.h"

namespace wetdem::diagnose {

// Exit codes of execute(): 0 done; 2 bad input (nothing run); 1 a run or the device failed.
std::unique_ptr<study::Commands> add_commands(CLI::App& cli);

}  // namespace wetdem::diagnose
