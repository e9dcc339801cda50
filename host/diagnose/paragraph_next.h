// The report paragraph's sentences on the next measurement (paragraph.cpp): the one that would separate a tie
// (next_experiment.h) and the one that would close an open interval (next_bound.h). Internal to diagnose/.
#pragma once

#include <string>

#include "diagnose/report.h"

namespace wetdem::diagnose {

// What measures an observable ("a washing / extraction assay or NMR: ..."), for the sentences below.
std::string assay_instrument(const std::string& observable);

// The tie's next experiment: the best single measurement, what remains after re-fit, how often to repeat it,
// a better pair, or the assay on every sample; the note when none was found; "" without proposals or note.
std::string next_sentence(const Report& r);

// The measurement that would close the chosen effect's open interval, when the stage ran; "" otherwise.
std::string bound_sentence(const Report& r);

}  // namespace wetdem::diagnose
