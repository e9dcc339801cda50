// Simulation parameters on the device (mirror of GpuParams in host/gpu/gpu_layout.h). Scalar layout (the C++
// struct's natural alignment, as std430 for these members). Run 0's block is also a uniform buffer
// (access.glsl: PRM()); ensembles reach the other runs' blocks by device address (ParamsRef).
#ifndef WETDEM_PARAMS_GLSL
#define WETDEM_PARAMS_GLSL
#include "table.glsl"

struct Contact {
  float E_star, G_star, phi_n, mu_s;
  float mu_r, phi_t, eta_r, pad;
};
struct Liquid {
  int64_t v_min, v_max;
  float f0_per_Rh, rupture_coef, unit_m3, range;
  uint enabled, dc_q16, pad0, pad1;
};
// Candidate effects of one interaction type (GpuEffects): [0] particle-particle, [1 + w] wall w.
struct Effects {
  float visc_eta, visc_smin, f0r_per_Rh, adhesion;
};
struct Params {
  Contact pp;
  Contact pw[3];
  Liquid lpp;
  Liquid lpw[3];
  int64_t drum_r2_ticks;
  int drum_r_ticks;
  int plate_z_ticks;
  int period_ticks;
  int cell_ticks;
  int grid_origin[3];
  int grid_dims[3];
  uint plate_present[2];
  uint plate_rotates[2];
  uint num_particles;
  uint liquid_on;
  float dt, h, inv_h, omega;
  float gravity[3];
  float skin;
  float cutoff_extra;
  float drum_r;
  uint hash_mask;
  float drum_r_frac;
  Effects fx[4];
  uint absorb_q64[2];  // liquid sinks: 64-bit loss fractions (lo, hi), see gpu_layout.h
  uint evap_q64[2];
  uint absorb_mode;  // 0 off, 1 rate, 2 instantaneous
  uint evap_on;
  uint runs;           // ensembles: runs in this system (1: a single run)
  uint run_stride;     // bytes between the parameter blocks of consecutive runs
  uint cells_per_run;  // each run has its own block of cells: runs never see each other
  uint wall_slots;     // wall records per particle: one per wall the drum has (access.glsl wall_slot)
};
layout(buffer_reference, scalar, buffer_reference_align = 16) readonly buffer ParamsRef { Params d; };
layout(set = 0, binding = 1, scalar) uniform ParamsU { Params d; } PRM0;
#endif
