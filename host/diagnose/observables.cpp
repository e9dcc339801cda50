#include "diagnose/observables.h"

namespace wetdem::diagnose {

const std::vector<ObservableSpec>& observable_catalogue() {
  constexpr double kInf = 1e300;
  static const std::vector<ObservableSpec> k = {
      {"aor_deg_mean", "deg", "video through the end plate (the paper's dynamic AoR, time-averaged)", "yes",
       0, 180},
      {"aor_deg_std", "deg",
       "the same video: the AoR's standard deviation over the window (the paper's cohesion indicator)", "yes",
       0, 180},
      {"aor_surface_deg", "deg",
       "the same images: angle of the fitted free surface (the flowing angle of rotating-drum testers)",
       "yes", 0, 90},
      {"cohesive_index_m", "m",
       "the same images: interface fluctuation (the cohesive index of rotating-drum testers)", "yes", 0,
       kInf},
      {"aor_drift_deg_per_rev", "deg/rev", "the same video over more revolutions: slope of the AoR", "yes",
       -kInf, kInf},
      {"aor_plate_deg", "deg", "video through the end plate: the bed next to the plate", "yes", 0, 180, true},
      {"surface_velocity_mps", "m/s", "PIV on the same video: downhill speed of the surface layer", "common",
       -kInf, kInf},
      {"flowing_layer_depth_m", "m", "PIV through the end plate: depth of the flowing layer", "common", 0,
       kInf},
      {"surface_agglomerate_size", "particles", "image analysis of the free surface: clumps it shows",
       "common", 1, kInf},
      {"surface_size_ratio", "-",
       "image analysis of the free surface: mean particle size there over the bed's (sieved) mean", "common",
       0, kInf},
      {"liquid_free_fraction", "-", "washing / extraction assay or NMR: liquid not in pores nor evaporated",
       "rare", 0, 1},
      {"aor_centre_deg", "deg", "tomography or PEPT: the bed mid-way between the plates", "rare", 0, 180,
       true},
      {"f_wet_mean", "-", "none: fraction of contacts that are bridged (a simulation quantity)",
       "no (simulation only)", 0, 1},
      {"agglomerate_size_mean", "particles", "none: components of the whole bridge network",
       "no (simulation only)", 1, kInf},
      {"drum_to_agglomerate_ratio", "-", "none: D over the bridge network's mean cluster",
       "no (simulation only)", 0, kInf},
      {"bridges_mean", "-", "none: number of liquid bridges", "no (simulation only)", 0, kInf},
      {"contacts_mean", "-", "none: number of touching contacts", "no (simulation only)", 0, kInf},
  };
  return k;
}

const ObservableSpec* find_observable(const std::string& name) {
  for (const ObservableSpec& o : observable_catalogue())
    if (o.name == name) return &o;
  return nullptr;
}

std::string observable_names() {
  std::string s;
  for (const ObservableSpec& o : observable_catalogue()) s += (s.empty() ? "" : ", ") + o.name;
  return s;
}

}  // namespace wetdem::diagnose
