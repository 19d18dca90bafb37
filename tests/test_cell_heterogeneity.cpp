// A heterogeneous ten Tusscher-Panfilov tissue: cell types, conductance scaling and drug block, and
// the reaction system with one model per group of particles.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "cardio/cell_heterogeneity.hpp"
#include "geometry/lattice.hpp"
#include "libsph/reaction/cell_simulation.hpp"
#include "libsph/reaction/reaction_system.hpp"

namespace {

using sph::Real;
using TP06 = sph::TenTusscherPanfilov2006;

double apd90(const TP06& model, double end = 1000) {
  std::vector<double> t, V;
  EXPECT_TRUE(sph::simulate_cell(model, sph::ReactionScheme::rbr_qss, 0.02, {0, 1, 52, 0, 1}, end, [&](double s, const auto& y) {
    t.push_back(s);
    V.push_back(y[0]);
  }));
  return sph::measure_action_potential(t, V, 0, end).duration();
}

// The M cell (G_Ks 0.098 instead of 0.392) has the longest action potential of the three, the
// reason for its place in the model (ten Tusscher & Panfilov 2006); the endocardial cell has almost
// no I_to, hence no notch after the upstroke.
TEST(CellTypes, MidMyocardialCellsHaveTheLongestActionPotential) {
  const double epi = apd90(TP06(TP06::Parameters::of(TP06::CellType::epicardial)));
  const double endo = apd90(TP06(TP06::Parameters::of(TP06::CellType::endocardial)));
  const double mid = apd90(TP06(TP06::Parameters::of(TP06::CellType::mid_myocardial)));
  std::printf("APD90 of the first beat: epicardial %.1f ms, endocardial %.1f ms, M %.1f ms\n", epi, endo, mid);
  EXPECT_GT(mid, epi);
  EXPECT_GT(mid, endo);
  EXPECT_EQ(TP06::Parameters::of(TP06::CellType::endocardial).g_to, 0.073);
  EXPECT_EQ(TP06::Parameters::of(TP06::CellType::mid_myocardial).g_Ks, 0.098);
}

// Half-maximal block at C = IC50 halves the conductance; blocking I_Kr by half prolongs the APD.
TEST(CellTypes, DrugBlockAtItsIc50HalvesTheConductanceAndProlongsTheApd) {
  cardio::CellHeterogeneity h;
  h.drugs = {{"g_Kr", 0.1, 1}};
  h.drug_concentration = 0.1;
  const auto groups = cardio::ten_tusscher_groups(h, 4, {}, {}, {});
  ASSERT_EQ(groups.models.size(), 1u);
  const auto& blocked = std::get<TP06>(groups.models[0]);
  EXPECT_DOUBLE_EQ(blocked.parameters().g_Kr, 0.5 * TP06::Parameters{}.g_Kr);
  const double control = apd90(TP06{}), block = apd90(blocked);
  std::printf("APD90 %.1f ms, with 50 %% I_Kr block %.1f ms (+%.1f %%)\n", control, block, 100 * (block / control - 1));
  EXPECT_GT(block, control);
  TP06::Parameters p;
  EXPECT_THROW(p.scale("g_Kx", 0.5), std::invalid_argument);
  cardio::CellHeterogeneity bad;
  bad.scalings = {{"g_Kr", 0.5, "endo"}};  // a layer without layers
  EXPECT_THROW(bad.check(), std::invalid_argument);
}

// Layers by the transmural coordinate and a scaling of the LV only: the groups and their counts.
TEST(CellTypes, GroupsFollowTheLayersAndRegions) {
  const std::size_t n = 10;
  std::vector<double> transmural, apicobasal(n, 0.5);
  std::vector<std::uint8_t> in_rv(n);
  for (std::size_t i = 0; i < n; ++i) {
    transmural.push_back((double(i) + 0.5) / double(n));
    in_rv[i] = i >= 5;
  }
  cardio::CellHeterogeneity h;
  h.transmural = true;
  h.scalings = {{"g_Kr", 0.5, "lv"}};
  const auto groups = cardio::ten_tusscher_groups(h, n, transmural, apicobasal, in_rv);
  // Particles 0-2 endo (lv), 3-4 mid (lv), 5 mid (rv), 6-9 epi (rv).
  ASSERT_EQ(groups.models.size(), 4u);
  EXPECT_EQ(groups.names[groups.group[0]], "endo lv");
  EXPECT_EQ(groups.names[groups.group[4]], "mid lv");
  EXPECT_EQ(groups.names[groups.group[5]], "mid rv");
  EXPECT_EQ(groups.names[groups.group[9]], "epi rv");
  EXPECT_EQ(groups.counts[groups.group[0]], 3u);
  EXPECT_DOUBLE_EQ(std::get<TP06>(groups.models[groups.group[4]]).parameters().g_Kr, 0.5 * TP06::Parameters{}.g_Kr);
  EXPECT_DOUBLE_EQ(std::get<TP06>(groups.models[groups.group[5]]).parameters().g_Kr, TP06::Parameters{}.g_Kr);
}

// The reaction system with three interleaved groups (lanes gathered per group) follows each
// particle's own model as the scalar step does, to the lanes' round-off.
TEST(CellTypes, GroupedLanesFollowEachParticlesOwnModel) {
  auto body = geometry::lattice_box<2>("cells", sph::Vec<2>(0, 0), sph::Vec<2>(Real(5), Real(4)), Real(1));  // 20 cells
  const std::size_t n = body.n_particles();
  std::vector<TP06> models{TP06(TP06::Parameters::of(TP06::CellType::epicardial)),
                           TP06(TP06::Parameters::of(TP06::CellType::endocardial)),
                           TP06(TP06::Parameters::of(TP06::CellType::mid_myocardial))};
  std::vector<std::uint16_t> group(n);
  for (std::size_t i = 0; i < n; ++i) group[i] = std::uint16_t((i * 7) % 3);
  sph::ReactionSystem<2, TP06> system(body, models, group, {});
  const sph::StimulusProtocol pulse{0, 1, 52, 0, 1};
  const double dt = 0.05;
  std::vector<TP06::State> scalar(n);
  for (std::size_t i = 0; i < n; ++i) scalar[i] = models[group[i]].initial_state();
  double largest = 0;
  std::vector<Real> stimulus(n);
  const auto V = body.field(system.potential_field());
  for (int step = 0; step < 8000; ++step) {
    const double t = step * dt;
    std::fill(stimulus.begin(), stimulus.end(), Real(pulse.average(t, dt)));
    system.advance(Real(t), Real(dt), stimulus);
    for (std::size_t i = 0; i < n; ++i) {
      sph::advance_cell(models[group[i]], scalar[i], pulse.average(t, dt), dt, sph::ReactionScheme::rbr_qss);
      largest = std::max(largest, std::abs(double(V[i]) - scalar[i][0]));
    }
  }
  std::printf("largest difference from the scalar step over 400 ms: %.3g mV\n", largest);
  EXPECT_LT(largest, 1e-6);
}

}  // namespace
