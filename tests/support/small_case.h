// A small drum case for end-to-end tests: ~360 particles in a 60 mm periodic slice, stiffness reduced 1e5
// (dt ~ 3.8e-4 s) and a fast drum (30 rpm), so that a run is a few thousand steps on lavapipe. Tests change
// it with --set overrides.
#pragma once

namespace wetdem::test {

inline constexpr const char* kSmall = R"(
name = "small"
scaling = 5
[material]
E = "1325 MPa"
G = "400 MPa"
restitution = 0.5
density = "900 kg/m3"
stiffness_reduction = 1e5          # dt ~ 3.8e-4 s: a short test, not a calibrated run
[friction]
mu_s = 0.8
mu_r = 0.3
[psd]
d10 = "506.0 um"
d25 = "712.7 um"
d50 = "904.6 um"
d75 = "1123 um"
d90 = "1345 um"
[liquid]
gamma = "21.7 mN/m"
theta = "30 deg"
content = "5 %"
v_min = 0
v_max = "1 %"
[drum]
diameter = "60 mm"
rpm = 30
fill = 0.36
periodic_slice = true
slice_thickness = "18 mm"
[run]
settle = "0.25 s"
duration = "0.7 s"
steady_state_start = "0.35 s"
sample_interval = "0.025 s"
seed = 3
steps_per_submit = 100
skin = "0.8 mm"                    # dt is 10x the paper's: a thicker skin keeps rebuilds rare
[output]
checkpoint_interval = 500
)";

}  // namespace wetdem::test
