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
#define CTL_GATE_ARGS 32
#define CTL_MAX_GATES 47
#define CTL_GATE_GROUPS (CTL_GATE_ARGS + 4 * CTL_MAX_GATES)
#define CTL_OWNER_ARGS (CTL_GATE_GROUPS + CTL_MAX_GATES)
#define CTL_OWNERS_NEEDED (CTL_OWNER_ARGS + 3)
#endif
