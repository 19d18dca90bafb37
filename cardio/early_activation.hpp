#pragma once
// The early-activation sites of the endocardial Purkinje surrogate and the stimuli they give.
//
// A Purkinje surrogate: every LV and RV endocardial particle is paced at
//   t_i = min_k (t_k + |x_i - c_k| / v_P)
// after the beat's origin, over the early-activation sites c_k with their times t_k (by default the
// LV apex at 0) and v_P the surrogate's speed (purkinje_velocity). The network that spreads the beat
// over the endocardium (Durrer et al. 1970, Circulation 41:899: the human ventricles activate in
// 60-80 ms from a few endocardial sites) is not resolved; the tissue conducts from the endocardium
// outwards. The pulses of particles whose onsets fall in the same splitting step share one
// stimulus region.
//
// The sites: the LV apex at 0 (lv_apex); a list "x,y,z@t;..." [mm, ms]; or the Durrer preset, four
// endocardial sites after Durrer et al. 1970, placed by the LDRB apico-basal coordinate a (0 apex, 1
// base; the bands below are fractions of the range of a over each endocardium) and the heart's
// frame (long axis, LV-to-RV direction r, and the anterior direction of a heart placed in the body
// as for the 12-lead ECG, cardio/pseudo_ecg.hpp):
//   LV anterior paraseptal, high (a in [0.7, 0.9], towards r + anterior), 0 ms;
//   LV central septal (a in [0.4, 0.6], towards r), 0 ms;
//   LV posterior paraseptal, a third from apex to base (a in [0.23, 0.43], towards r - anterior), 0 ms;
//   RV anterior free wall near the anterior papillary muscle (a in [0.4, 0.6], anterior), 5 ms
// (Durrer: the three LV areas are excited 0-5 ms after the onset, the RV 5-10 ms).

#include <span>
#include <string>
#include <vector>

#include "cardio/heart_geometry.hpp"
#include "cardio/monodomain.hpp"

namespace cardio {

/// An early-activation site of the endocardial Purkinje surrogate: position [mm] and time [ms].
struct EarlySite {
  sph::Vec<3> position;
  double time = 0;
};

/// "x,y,z@t;..." into sites; throws sph::ParameterError naming 'early_site_list' and the entry.
std::vector<EarlySite> parse_early_sites(const std::string& text);

/// The LV endocardial particle farthest from the base (along -base normal): the apex stimulus site.
/// Throws std::invalid_argument if no particle is labelled LV endocardium.
sph::Vec<3> lv_apex(const HeartGeometry& g, std::span<const sph::Vec<3>> x);

/// The sites of `early_sites` ("lv_apex": `apex` at 0; "list": parse_early_sites(list); "durrer":
/// the preset above) for the particles at x with the labels and LDRB coordinates of g. Throws
/// sph::ParameterError naming the parameter when the geometry cannot place them.
std::vector<EarlySite> early_activation_sites(const std::string& early_sites, const std::string& list, const HeartGeometry& g,
                                              std::span<const sph::Vec<3>> x, const sph::Vec<3>& apex);

/// The stimuli of the surrogate (see above) from `sites` at speed `velocity` [mm/ms]: one region per
/// splitting step `bin` [ms] of onsets, each with `first`'s protocol started bin k later. Throws
/// sph::ParameterError if no particle is labelled LV or RV endocardium.
std::vector<Monodomain<3>::StimulusRegion> endocardial_stimuli(const std::vector<EarlySite>& sites, double velocity, double bin,
                                                              const sph::StimulusProtocol& first,
                                                              std::span<const std::int8_t> labels,
                                                              std::span<const sph::Vec<3>> x);

}  // namespace cardio
