// The report paragraph's sentences on what a table is silent on (paragraph.cpp), each with its leading
// space, "" when there is nothing to say. Internal to diagnose/.
#pragma once

#include <string>

#include "diagnose/report.h"

namespace wetdem::diagnose {

// The candidates this table cannot show (power.h): what the verdict is silent on, where each comes closest,
// and where it would show.
std::string blind_sentence(const Report& r);

// The candidates the table shows only past the file's strongest probe (power.h, extend_reach).
std::string strong_only_sentence(const Report& r);

// After a `no_gap`, what the table rules out of each candidate (limits.h), a sink's with its rate free too.
std::string limits_sentence(const Report& r);

}  // namespace wetdem::diagnose
