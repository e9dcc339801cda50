// The neighbour loop of a rebuild (nbr_count, and nbr_fill where the count pass could not keep a particle's
// candidates): every particle j != i in the 27 cells around i (periodic in z) whose surface gap is below
// cutoff_extra = S_c,max + skin. The order is deterministic (cells in fixed order, particles in sorted order),
// and the test is symmetric in i, j (r_i + r_j is commutative in floating point; d - r_i - r_j is not).
// Most of the 27 cells' particles lie beyond the reach (the cells' volume is ~9x the neighbour sphere's): an
// integer box test on the tick difference rejects them before their fraction and radius are loaded. It is
// conservative (reach = the cell edge 2 r_max + cutoff_extra plus a margin for float rounding of the exact
// test), so the list is the one the exact test alone gives.
#ifndef WETDEM_NEIGHBOURS_GLSL
#define WETDEM_NEIGHBOURS_GLSL
#include "geom.glsl"

// The particles j in [b, e) of the sorted order that lie within reach of i (the variables of FOR_EACH_NEIGHBOUR
// below): an integer box test on the tick difference first, then the exact gap test.
#define NEIGHBOURS_IN_RANGE_(b, e, VISIT)                                                         \
  for (uint j = b; j < e; ++j) {                                                                  \
    if (j == i) continue;                                                                         \
    ivec3 D_ = tick_delta(pi_, load_i4(pos_a_, j).xyz, P.period_ticks);                            \
    if (any(greaterThan(abs(D_), ivec3(reach_)))) continue;                                       \
    vec3 d_ = (vec3(D_) + (fi_ - load_v4(fr_a_, j).xyz)) * P.h;                                    \
    if (length(d_) - (ri_ + props_.v[j].x) < P.cutoff_extra) { VISIT; }                             \
  }

// Calls VISIT(j) for every neighbour j of sorted particle i in the set s. In an ensemble each run has its own
// block of cells (cell_key.comp), so only the particle's own run is searched; its block is read off its sorted
// key (reading the run table here instead made llvmpipe's compiled loop crash).
#define FOR_EACH_NEIGHBOUR(i, s, P, VISIT)                                                        \
  {                                                                                               \
    uint64_t pos_a_ = paddr(s, PF_POS), fr_a_ = paddr(s, PF_FRAC);                                \
    Vec4s props_ = Vec4s(paddr(s, PF_PROPS));                                                     \
    Uints cs_ = Uints(T().cell_start), ce_ = Uints(T().cell_end);                                 \
    ivec3 pi_ = load_i4(pos_a_, i).xyz;                                                            \
    uint block_ = (Uints(T().cell_key).v[i] / P.cells_per_run) * P.cells_per_run;                 \
    vec3 fi_ = load_v4(fr_a_, i).xyz;                                                             \
    float ri_ = props_.v[i].x;                                                                    \
    bool esc_;                                                                                    \
    ivec3 c0_ = cell_of(pi_, P, esc_);                                                            \
    ivec3 dims_ = ivec3(P.grid_dims[0], P.grid_dims[1], P.grid_dims[2]);                          \
    int zspan_ = (P.period_ticks > 0 && dims_.z < 3) ? dims_.z : 3;                              \
    int reach_ = P.cell_ticks + (P.cell_ticks >> 10) + 4;                                         \
    if (P.hash_mask == 0u) {                                                                      \
      /* dense grid: x is the fastest cell index and the particles are sorted by cell, so the three   \
         cells x-1..x+1 of a row hold one contiguous range of particles. One loop per row (9, not 27) \
         visits the same particles in the same order, with less divergence between SIMD lanes. */    \
      int xlo_ = max(c0_.x - 1, 0), xhi_ = min(c0_.x + 1, dims_.x - 1);                          \
      for (int dz_ = -1; dz_ < zspan_ - 1; ++dz_)                                                 \
        for (int dy_ = -1; dy_ <= 1; ++dy_) {                                                     \
          ivec3 c_ = ivec3(xlo_, c0_.y + dy_, c0_.z + dz_);                                       \
          if (P.period_ticks > 0) c_.z = (c_.z + dims_.z) % dims_.z;                              \
          if (c_.y < 0 || c_.y >= dims_.y || c_.z < 0 || c_.z >= dims_.z) continue;               \
          uint k0_ = cell_index(c_, P) + block_;                                                  \
          uint b_ = 0xFFFFFFFFu, e_ = 0u;                                                         \
          for (uint k_ = k0_; k_ <= k0_ + uint(xhi_ - xlo_); ++k_) {                              \
            uint cb_ = cs_.v[k_];                                                                 \
            if (cb_ == 0xFFFFFFFFu) continue;                                                     \
            b_ = min(b_, cb_);                                                                    \
            e_ = ce_.v[k_];                                                                       \
          }                                                                                       \
          NEIGHBOURS_IN_RANGE_(b_, e_, VISIT)                                                     \
        }                                                                                         \
    } else {                                                                                      \
      /* hashed grid: two neighbour cells may share a bucket; visit each bucket once */          \
      uint seen_[27];                                                                             \
      uint nseen_ = 0u;                                                                           \
      for (int dz_ = -1; dz_ < zspan_ - 1; ++dz_)                                                 \
        for (int dy_ = -1; dy_ <= 1; ++dy_)                                                       \
          for (int dx_ = -1; dx_ <= 1; ++dx_) {                                                   \
            ivec3 c_ = c0_ + ivec3(dx_, dy_, dz_);                                                \
            if (P.period_ticks > 0) c_.z = (c_.z + dims_.z) % dims_.z;                            \
            uint k_ = cell_index(c_, P) + block_;                                                 \
            bool dup_ = false;                                                                    \
            for (uint q_ = 0u; q_ < nseen_; ++q_) dup_ = dup_ || seen_[q_] == k_;                 \
            if (dup_) continue;                                                                   \
            seen_[nseen_++] = k_;                                                                 \
            uint b_ = cs_.v[k_];                                                                  \
            if (b_ == 0xFFFFFFFFu) continue;                                                      \
            uint e_ = ce_.v[k_];                                                                  \
            NEIGHBOURS_IN_RANGE_(b_, e_, VISIT)                                                   \
          }                                                                                       \
    }                                                                                             \
  }
#endif
