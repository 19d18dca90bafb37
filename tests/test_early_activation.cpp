// The early-activation sites of the endocardial Purkinje surrogate (cardio/early_activation.hpp):
// the site list and its refusals, the LV apex, the Durrer sites' refusals, and the stimuli the
// sites give, t_i = min_k (t_k + |x_i - c_k| / v_P), binned by splitting step.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cardio/early_activation.hpp"
#include "libsph/io/parameters.hpp"

namespace {

using sph::Real;
using Vec3 = sph::Vec<3>;

bool throws_naming(const std::string& text, const std::string& part) {
  try {
    (void)cardio::parse_early_sites(text);
  } catch (const sph::ParameterError& e) {
    return std::string(e.what()).find(part) != std::string::npos;
  }
  return false;
}

TEST(EarlyActivation, SiteListParsesPositionsAndTimesAndRefusesBadEntries) {
  const auto sites = cardio::parse_early_sites("1,2,3@0; 4.5,-5,6@5 ;");
  ASSERT_EQ(sites.size(), 2u);
  EXPECT_EQ(sites[1].position, Vec3(Real(4.5), -5, 6));
  EXPECT_EQ(sites[1].time, 5);
  EXPECT_TRUE(throws_naming("1,2@0", "entry '1,2@0'"));
  EXPECT_TRUE(throws_naming("1,2,3@-1", "early_site_list"));
  EXPECT_TRUE(throws_naming("1,2,3@1 x", "early_site_list"));
  EXPECT_TRUE(throws_naming(" ; ", "names no site"));
}

// Particles on the z axis, z = 0..5; labels: LV endocardium at z = 0, 1, 4; RV endocardium at 2;
// none elsewhere. The base normal is +z, so the LV apex is the LV particle of lowest z.
struct Column {
  cardio::HeartGeometry g;
  std::vector<Vec3> x;
  Column() {
    for (int k = 0; k < 6; ++k) x.push_back(Vec3(0, 0, Real(k)));
    g.labels = {cardio::label_lv_endo, cardio::label_lv_endo, cardio::label_rv_endo, cardio::label_none, cardio::label_lv_endo,
                cardio::label_epi};
  }
};

TEST(EarlyActivation, LvApexAndTheSitesOfEachChoice) {
  Column c;
  EXPECT_EQ(cardio::lv_apex(c.g, c.x), Vec3::Zero());
  c.g.base_normal = -c.g.base_normal;  // the apex is now at the top
  EXPECT_EQ(cardio::lv_apex(c.g, c.x), Vec3(0, 0, 4));
  const auto apex = cardio::early_activation_sites("lv_apex", "", c.g, c.x, Vec3(1, 2, 3));
  ASSERT_EQ(apex.size(), 1u);
  EXPECT_EQ(apex[0].position, Vec3(1, 2, 3));
  EXPECT_EQ(cardio::early_activation_sites("list", "0,0,1@2", c.g, c.x, Vec3::Zero())[0].time, 2);
  // Durrer places its sites by the LDRB apico-basal coordinate, which this geometry lacks.
  EXPECT_THROW(cardio::early_activation_sites("durrer", "", c.g, c.x, Vec3::Zero()), sph::ParameterError);
  c.g.labels.assign(6, cardio::label_none);
  EXPECT_THROW(cardio::lv_apex(c.g, c.x), std::invalid_argument);
}

TEST(EarlyActivation, EndocardialStimuliStartAtTheSurrogatesDelayBinnedBySplittingStep) {
  Column c;
  // Sites at z = 0 (t = 0) and z = 4 (t = 1 ms), v_P = 2 mm/ms: delays 0, 0.5, 1 (RV, from z = 0),
  // and 1 at z = 4 (its own site), binned by 0.5 ms steps.
  const std::vector<cardio::EarlySite> sites{{Vec3::Zero(), 0}, {Vec3(0, 0, 4), 1}};
  const sph::StimulusProtocol first(10, 2, 50, 800, 3);
  const auto stimuli = cardio::endocardial_stimuli(sites, 2, 0.5, first, c.g.labels, c.x);
  ASSERT_EQ(stimuli.size(), 3u);
  EXPECT_EQ(stimuli[0].particles, (std::vector<std::size_t>{0}));
  EXPECT_EQ(stimuli[1].particles, (std::vector<std::size_t>{1}));
  EXPECT_EQ(stimuli[2].particles, (std::vector<std::size_t>{2, 4}));
  EXPECT_EQ(stimuli[2].name, "endocardium +1.00 ms");
  EXPECT_EQ(stimuli[1].protocol.start, 10.5);
  EXPECT_EQ(stimuli[2].protocol.start, 11);
  EXPECT_EQ(stimuli[2].protocol.duration, 2);
  EXPECT_EQ(stimuli[2].protocol.period, 800);
  EXPECT_EQ(stimuli[2].protocol.count, 3);
  std::vector<std::int8_t> unlabelled(6, cardio::label_none);
  EXPECT_THROW(cardio::endocardial_stimuli(sites, 2, 0.5, first, unlabelled, c.x), sph::ParameterError);
}

}  // namespace
