// Size segregation at the free surface (drum.md finding 7: in dry and lightly wet beds the large particles
// gather at the free surface; cohesion suppresses it). Pure function of a state and its fitted surface.
//
// surface_size_ratio = number-mean radius of the surface layer / number-mean radius of the bed, the surface
// layer being fit_surface's (surface.h): the one-monolayer of highest particles (by centre) of each fitted
// column. > 1: large particles at the surface. Even a perfectly mixed bed reads somewhat above 1, since a
// large particle resting on the surface has its centre higher than a small one beside it: compare a bed with
// itself (the settled bed before rotation, a wet bed against the dry one), not with 1.
#pragma once

#include "app/observe/surface.h"
#include "wetdem/state.h"

namespace wetdem::observe {

// NaN when the surface was not fitted (sf.valid false) or its layer is empty.
double surface_size_ratio(const SystemState& s, const SurfaceResult& sf);

}  // namespace wetdem::observe
