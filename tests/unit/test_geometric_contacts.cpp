// Geometric contacts (lib/network/geometric_contacts): a hand-built Lees–Edwards frame with
// known gaps, one pair of them through the sheared image, and known gaps one step earlier.
#include "network/geometric_contacts.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

namespace granflow::network {
namespace {

constexpr double kDt = 0.01, kRate = 0.1;

// Radii 0.5. Pairs: (0, 1) gap 1e-3, was overlapping one step earlier (separating);
// (2, 3) gap 1e-2, 2e-2 one step earlier (approaching); (4, 5) gap 5e-4 through the image
// one row up (offset 3, moving at +γ̇·Ly = 2 in x relative to grain 5), 5.1e-4 one step
// earlier with the image's speed counted (8.1e-4 without it, more with its sign flipped).
io::Frame frame() {
  io::Frame f;
  f.box.lx = 20;
  f.box.ly = 20;
  f.box.offset = 3;
  f.position = {{5, 5}, {6.001, 5}, {10, 10}, {10, 11.01}, {12, 19.6}, {9, 0.6005}, {15, 5}};
  f.velocity = {{0, 0}, {0.5, 0}, {0, 0}, {0, -1}, {2.5, 0}, {0, 0}, {0, 0}};
  f.contacts.pair = {{0, 1}};
  f.contacts.binary_force = {7.0};
  f.contacts.branch = {{-1.001, 0}};
  f.contacts.age = {3};
  f.has_contacts = true;
  return f;
}

const std::vector<double> kRadius(7, 0.5);

TEST(GeometricContacts, GapsDecideWhichPairsTouch) {
  const io::Frame f = frame();
  EXPECT_EQ(geometric_contacts(f, kRadius, 4e-4, kDt, kRate).size(), 0u);
  const ContactRecords a = geometric_contacts(f, kRadius, 6e-4, kDt, kRate);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a.pair[0][0], 4);
  EXPECT_EQ(a.pair[0][1], 5);
  // r_4 − (r_5 + (offset, Ly)) = (0, −1.0005).
  EXPECT_NEAR(a.branch[0].x(), 0.0, 1e-12);
  EXPECT_NEAR(a.branch[0].y(), -1.0005, 1e-12);
  const ContactRecords b = geometric_contacts(f, kRadius, 2e-3, kDt, kRate);
  ASSERT_EQ(b.size(), 2u);
  EXPECT_EQ(b.pair[0][0], 0);
  EXPECT_EQ(b.pair[0][1], 1);
  const ContactRecords c = geometric_contacts(f, kRadius, 0.011, kDt, kRate);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c.pair[1][0], 2);
  EXPECT_EQ(c.pair[1][1], 3);
  EXPECT_NEAR(c.branch[1].y(), -1.01, 1e-12);
}

TEST(GeometricContacts, LongLivedWhenWithinTheGapOneStepEarlier) {
  const io::Frame f = frame();
  const ContactRecords c = geometric_contacts(f, kRadius, 0.011, kDt, kRate);
  ASSERT_EQ(c.size(), 3u);
  EXPECT_EQ(c.age[0], 2);  // (0, 1): overlapping one step earlier
  EXPECT_EQ(c.age[1], 1);  // (2, 3): 2e-2 apart one step earlier
  EXPECT_EQ(c.age[2], 2);  // (4, 5)
  // Through the image: 5.1e-4 one step earlier counts the image's speed, not 8.1e-4.
  const ContactRecords a = geometric_contacts(f, kRadius, 6e-4, kDt, kRate);
  ASSERT_EQ(a.size(), 1u);
  EXPECT_EQ(a.age[0], 2);
  const ContactRecords tight = geometric_contacts(f, kRadius, 5.05e-4, kDt, kRate);
  ASSERT_EQ(tight.size(), 1u);
  EXPECT_EQ(tight.age[0], 1);
}

TEST(GeometricContacts, BinaryForceOfTheRecordedPairOnly) {
  const ContactRecords c = geometric_contacts(frame(), kRadius, 0.011, kDt, kRate);
  ASSERT_EQ(c.binary_force.size(), 3u);
  EXPECT_EQ(c.binary_force[0], 7.0);
  EXPECT_EQ(c.binary_force[1], 0.0);
  EXPECT_EQ(c.binary_force[2], 0.0);
  EXPECT_TRUE(c.normal_force.empty());
}

TEST(GeometricContacts, RefusesBadArguments) {
  const io::Frame f = frame();
  EXPECT_THROW(geometric_contacts(f, kRadius, -1e-3, kDt, kRate), std::invalid_argument);
  EXPECT_THROW(geometric_contacts(f, kRadius, std::numeric_limits<double>::quiet_NaN(), kDt, kRate),
               std::invalid_argument);
  EXPECT_THROW(geometric_contacts(f, kRadius, 1e-3, 0, kRate), std::invalid_argument);
  EXPECT_THROW(geometric_contacts(f, std::vector<double>(3, 0.5), 1e-3, kDt, kRate), std::invalid_argument);
}

}  // namespace
}  // namespace granflow::network
