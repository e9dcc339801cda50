// Host mirrors of the GPU-side layouts in shaders/common/{params,ctl,table}.glsl (std430). Any change here
// must be made there too; the static_asserts catch size drift.
#pragma once

#include <cstdint>

namespace wetdem::gpu {

// Contact-law coefficients of one interaction type (physics.md §1-3), float32 on the device.
struct GpuContact {
  float E_star, G_star, phi_n, mu_s;
  float mu_r, phi_t, eta_r, pad;
};
static_assert(sizeof(GpuContact) == 32);

// Liquid coefficients of one interaction type (§4-5). Volumes in integer units.
struct GpuLiquid {
  int64_t v_min, v_max;
  float f0_per_Rh;     // 2 pi gamma cos(theta): f0 = f0_per_Rh * R_h
  float rupture_coef;  // 1 + theta/2: S_c = rupture_coef * V^(1/3)
  float unit_m3;       // volume of one liquid unit
  float range;         // interaction range beyond contact (m): S_c,max for this type
  uint32_t enabled;
  uint32_t dc_q16;  // distribution coefficient d_c in 1/65536
  uint32_t pad0, pad1;
};
static_assert(sizeof(GpuLiquid) == 48);

// Candidate effects of one interaction type (diagnosis.md §3; docs/model.md "Candidate effects"). Zero = off;
// with theta_r = theta, f0r_per_Rh equals GpuLiquid::f0_per_Rh bit for bit.
struct GpuEffects {
  float visc_eta;    // viscosity eta (Pa s): Pitois lubrication on bridged pairs
  float visc_smin;   // lubrication cut-off S_min (m)
  float f0r_per_Rh;  // 2 pi gamma cos(theta_r): pull of a separated bridge (hysteresis)
  float adhesion;    // 1.5 pi w: JKR pull-off F_a = adhesion * R* while touching (cohesion)
};
static_assert(sizeof(GpuEffects) == 16);

struct GpuParams {
  GpuContact pp;
  GpuContact pw[3];
  GpuLiquid lpp;
  GpuLiquid lpw[3];
  int64_t drum_r2_ticks;  // (R/h)^2, for exact cylinder gaps
  int32_t drum_r_ticks;
  int32_t plate_z_ticks;   // L/2 in ticks (plates at +-)
  int32_t period_ticks;    // periodic z period in ticks (0 = not periodic)
  int32_t cell_ticks;      // cell edge in ticks
  int32_t grid_origin[3];  // lowest corner of the cell grid, ticks
  int32_t grid_dims[3];
  uint32_t plate_present[2];
  uint32_t plate_rotates[2];
  uint32_t num_particles;
  uint32_t liquid_on;  // any liquid interaction enabled: run the liquid passes
  float dt, h, inv_h, omega;
  float gravity[3];
  float skin;          // neighbour skin (m)
  float cutoff_extra;  // list keeps pairs with gap < cutoff_extra = S_c,max + skin (m)
  float drum_r;        // m
  uint32_t hash_mask;  // 0: dense cell grid; else cells are hashed into hash_mask + 1 buckets
  float drum_r_frac;   // R/h - drum_r_ticks
  GpuEffects fx[4];    // candidate effects: [0] particle-particle, [1 + w] wall w
  // Liquid sinks (pore absorption, evaporation): 64-bit loss fractions as (lo, hi) words, see
  // loss_fraction_q64 in params.h; absorb_mode 0 off, 1 rate, 2 instantaneous (all the film).
  uint32_t absorb_q64[2];
  uint32_t evap_q64[2];
  uint32_t absorb_mode;
  uint32_t evap_on;
  uint32_t runs;           // ensembles: runs in this system (1: a single run)
  uint32_t run_stride;     // bytes between the parameter blocks of consecutive runs (sizeof(GpuParams))
  uint32_t cells_per_run;  // each run has its own block of cells
  uint32_t wall_slots;     // wall records per particle: one per wall the drum has (access.glsl wall_slot)
};
static_assert(sizeof(GpuParams) ==
              32 * 4 + 48 * 4 + 8 + 4 * 4 + 12 * 2 + 8 * 2 + 8 + 16 + 12 + 12 + 8 + 16 * 4 + 24 + 16);
static_assert(sizeof(GpuParams) % 16 == 0, "parameter blocks of an ensemble are packed back to back");

// Control block (uint32 words); see shaders/common/ctl.glsl.
namespace ctl {
inline constexpr uint32_t kHaltForRebuild = 2;  // ctl[kHalt] of a split-rebuild step (1: list overflow)
enum : uint32_t {
  kHalt = 0,
  kRebuild = 1,
  kForceRebuild = 2,
  kMaxDispBits = 3,
  kEntries = 4,
  kEntriesNeeded = 5,
  kOwners = 6,  // owner entries of the current list (length of the owner list)
  kParity = 7,
  kLostBridges = 8,
  kEscaped = 9,
  kFormations = 10,
  kRuptures = 11,
  kRebuilds = 12,
  kStepsDone = 13,
  kOverflows = 14,
  kMirrorErrors = 15,
  kEntryArgs = 16,    // uvec4: dispatch over the current list's entries
  kBuildArgs = 20,    // uvec4: dispatch over the list being built (written after its scan)
  kLostArgs = 24,     // uvec4: lost-bridge check over the old list (rebuild steps only)
  kCapacity0 = 28,    // entry capacity of pair set 0 (kCapacity0 + 1: set 1)
  kLiquidSteps = 30,  // fused step: steps whose liquid passes ran (the gate was open)
  kDrifted = 31,      // fused step: 1 while the particles hold x^(n+1), v^(n+1/2) (the next drift is done)
  kGateArgs = 32,     // kMaxGates uvec4 slots: rebuild-gated dispatch sizes
  kMaxGates = 40,
  kGateGroups = kGateArgs + 4 * kMaxGates,  // kMaxGates uints: nominal group counts of the gated slots
  kOwnerArgs = kGateGroups + kMaxGates,     // uvec3: dispatch over the current list's owner entries
  kOwnersNeeded = kOwnerArgs + 3,           // owner entries of the list being built (after its scan)
  // The fused step (ARCHITECTURE.md "Passes of a step"); see ctl.glsl.
  kCandPair = kOwnersNeeded + 1,  // liquid event candidates flagged by pair_force
  kCandWall,                      // ... by the walls in gather_kick
  kCandStep,                      // both, for the liquid passes of this step
  kDoneGroups,                    // workgroups of the current pass that finished (last-group test)
  kLiqArgs,                       // 3 uvec3: sizes of the gated liquid passes 4b, 4c, 4d
  kStepArgs = kLiqArgs + 9,       // uvec3: the per-particle passes of a step (zero after a halt)
  // The skin test (step_control.glsl): the second largest displacement, the steps since the list was built,
  // the rule (kSkin* bits, from SystemOptions; written by upload and restore, never by a shader), and the two
  // largest displacements in the drum's frame.
  kMaxDisp2Bits = kStepArgs + 3,
  kSinceBuild,
  kSkinRule,
  kMaxFrameDispBits,
  kMaxFrameDisp2Bits,
  kWords = 272,
};
static_assert(kMaxFrameDisp2Bits < kWords);
// kSkinRule bits.
inline constexpr uint32_t kSkinDrumFrame = 1;  // also displacements from the reference turned with the drum
inline constexpr uint32_t kSkinTopTwo = 2;     // rebuild when the two largest add up to the skin
}  // namespace ctl

// Push-constant mode bits of the passes the fused step records in several ways (shaders/common/modes.glsl).
namespace mode {
enum : uint32_t {
  kGather = 1,           // gather_kick: pair results + walls, second half kick
  kKickDrift = 2,        // gather_kick: first half kick of the next step and its drift
  kShare = 4,            // gather_kick: liquid pass 4a
  kFinish = 8,           // gather_kick: last workgroup gates the liquid passes / decides the rebuild
  kSplit = 16,           // split rebuilds
  kGate = 32,            // liquid passes closed on steps without event candidates
  kSinks = 64,           // a liquid sink is on: 4c runs every step
  kLiquid = 128,         // liquid passes follow
  kUnlessDrifted = 256,  // a submit's first kick-drift: skip when already done
};
enum : uint32_t { kAtomic = 1, kGated = 2, kLqFinish = 4, kLqSplit = 8 };  // liquid passes 4b-4d
}  // namespace mode
// Sampling words (System::sample_runs), mirror of shaders/common/sample.glsl.
namespace smp {
enum : uint32_t {
  kPairs = 0,     // bridged pairs the pass wrote to the compact list (may exceed the capacity)
  kCapacity = 1,  // entries of the compact list
  kHead = 4,      // words before run 0's block
  kRun = 32,      // words per run
  // Within a run's block (int64: two words, low first).
  kMass = 0,
  kMx = 2,
  kMy = 4,
  kMz = 6,
  kKe = 8,
  kFilms = 10,
  kPores = 12,
  kEvap = 14,
  kWallLiq = 16,
  kPairLiq = 18,
  kContacts = 20,
  kBridges = 21,
  kTouchBridged = 22,
  kWallContacts = 23,
  kWallBridges = 24,
  kNonFinite = 25,
  kMaxOverlap = 26,  // float bits
  kMaxMass = 27,     // float bits
  kMaxKe = 28,       // float bits
  kExtent = 29,      // float, written by the host: the drum's half extent max(R, L/2)
};
inline constexpr int kMassBits = 34, kKeBits = 36;  // fixed-point scales (sample.glsl)
}  // namespace smp

}  // namespace wetdem::gpu
