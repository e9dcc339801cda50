// Push-constant mode bits (pc.arg0) of the passes the fused step records in several ways; mirror of
// host/gpu/gpu_layout.h, namespace mode.
#ifndef WETDEM_MODES_GLSL
#define WETDEM_MODES_GLSL
// gather_kick
#define GK_GATHER 1u        // sum the pair results and the walls, second half kick (§0)
#define GK_KICK_DRIFT 2u    // first half kick of the next step and its drift (§0)
#define GK_SHARE 4u         // liquid pass 4a (rupture shares), fused
#define GK_FINISH 8u        // last workgroup: liquid gate, and the rebuild decision when no liquid pass follows
#define GK_SPLIT 16u        // split rebuilds (decide_rebuild)
#define GK_GATE 32u         // close the liquid passes on steps without event candidates
#define GK_SINKS 64u        // liquid sinks on in some run: the film pass 4c runs every step
#define GK_LIQUID 128u      // liquid passes follow in this step
#define GK_UNLESS_DRIFTED 256u  // the first kick-drift of a submit: nothing to do when the last step did it
// liquid passes 4b-4d
#define LQ_ATOMIC 1u  // overflow and takes go straight to the films with integer atomics (no 4e)
#define LQ_GATED 2u   // 4c: count forming contacts only when the step has formation candidates
#define LQ_FINISH 4u  // 4d: last workgroup takes the rebuild decision
#define LQ_SPLIT 8u   // ... with split rebuilds
#endif
