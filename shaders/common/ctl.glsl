// Control block: flags, counters and indirect dispatch sizes shared by every pass (mirror of
// host/gpu/gpu_layout.h, namespace ctl). Only integer atomics touch it: results stay deterministic.
#ifndef WETDEM_CTL_GLSL
#define WETDEM_CTL_GLSL
#include "table.glsl"
#define CTL_HALT 0
#define CTL_HALT_FOR_REBUILD 2u  // CTL_HALT value of a split-rebuild step; 1 = list overflow
#define CTL_REBUILD 1
#define CTL_FORCE_REBUILD 2
#define CTL_MAX_DISP 3
#define CTL_ENTRIES 4
#define CTL_ENTRIES_NEEDED 5
#define CTL_OWNERS 6
#define CTL_PARITY 7
#define CTL_LOST 8
#define CTL_ESCAPED 9
#define CTL_FORMATIONS 10
#define CTL_RUPTURES 11
#define CTL_REBUILDS 12
#define CTL_STEPS 13
#define CTL_OVERFLOWS 14
#define CTL_MIRROR_ERR 15
#define CTL_ENTRY_ARGS 16
#define CTL_BUILD_ARGS 20
#define CTL_LOST_ARGS 24
#define CTL_CAPACITY0 28
#define CTL_LIQ_STEPS 30  // fused step: steps whose liquid passes ran (the gate was open)
#define CTL_DRIFTED 31    // fused step: 1 while the particles hold x^(n+1), v^(n+1/2) (the next drift is done)
#define CTL_GATE_ARGS 32
#define CTL_MAX_GATES 40
#define CTL_GATE_GROUPS (CTL_GATE_ARGS + 4 * CTL_MAX_GATES)
#define CTL_OWNER_ARGS (CTL_GATE_GROUPS + CTL_MAX_GATES)
#define CTL_OWNERS_NEEDED (CTL_OWNER_ARGS + 3)
// The fused step (ARCHITECTURE.md "Passes of a step"):
#define CTL_CAND_PAIR (CTL_OWNERS_NEEDED + 1)  // liquid event candidates flagged by pair_force (CAND_* bits)
#define CTL_CAND_WALL (CTL_CAND_PAIR + 1)      // ... by the walls in gather_kick
#define CTL_CAND_STEP (CTL_CAND_WALL + 1)      // both, for the liquid passes of this step
#define CTL_DONE_GROUPS (CTL_CAND_STEP + 1)    // workgroups of the current pass that finished (last-group test)
#define CTL_LIQ_ARGS (CTL_DONE_GROUPS + 1)     // 3 uvec3: sizes of the gated liquid passes 4b, 4c, 4d
#define CTL_STEP_ARGS (CTL_LIQ_ARGS + 9)      // uvec3: the per-particle passes of a step (zero after a halt)
#define CTL_MAX_DISP2 (CTL_STEP_ARGS + 3)  // the second largest displacement (float bits)
#define CTL_SINCE_BUILD (CTL_MAX_DISP2 + 1) // steps since the list was built
#define CTL_SKIN_RULE (CTL_SINCE_BUILD + 1) // SKIN_* bits, written by the host
#define CTL_MAX_FDISP (CTL_SKIN_RULE + 1)   // the largest displacement in the drum's frame (float bits)
#define CTL_MAX_FDISP2 (CTL_MAX_FDISP + 1)  // ... and the second largest
#define SKIN_DRUM_FRAME 1u
#define SKIN_TOP_TWO 2u
#define CAND_RUPT 1u
#define CAND_FORM 2u
#endif
