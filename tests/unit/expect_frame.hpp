#pragma once
// Field-by-field comparisons of stored frames and contact records, exact to the bit
// (EXPECT_EQ on the vectors): the trajectory round trips and the checkpoint round trips
// promise the same values, not close ones.
#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

#include "io/trajectory.hpp"

namespace granflow::test_support {

// Positions, velocities, orientations, angular velocities and the box of two frames.
inline void expect_same_grains(const io::Frame& a, const io::Frame& b) {
  EXPECT_EQ(a.position, b.position);
  EXPECT_EQ(a.velocity, b.velocity);
  EXPECT_EQ(a.orientation, b.orientation);
  EXPECT_EQ(a.angular_velocity, b.angular_velocity);
  EXPECT_EQ(a.box.lx, b.box.lx);
  EXPECT_EQ(a.box.ly, b.box.ly);
  EXPECT_EQ(a.box.periodic_y, b.box.periodic_y);
  EXPECT_EQ(a.box.offset, b.box.offset);
}

// Every column of two contact lists.
inline void expect_same_contacts(const ContactRecords& a, const ContactRecords& b) {
  EXPECT_EQ(a.size(), b.size());
  EXPECT_EQ(a.pair, b.pair);
  EXPECT_EQ(a.normal_force, b.normal_force);
  EXPECT_EQ(a.tangential_force, b.tangential_force);
  EXPECT_EQ(a.branch, b.branch);
  EXPECT_EQ(a.binary_force, b.binary_force);
  EXPECT_EQ(a.pre_normal_velocity, b.pre_normal_velocity);
  EXPECT_EQ(a.age, b.age);
}

// A frame read back against the one written (a frame written without contacts reads
// back with an empty list).
inline void expect_same_frame(const io::Frame& read, const io::Frame& written) {
  EXPECT_EQ(read.step, written.step);
  EXPECT_EQ(read.time, written.time);
  expect_same_grains(read, written);
  expect_same_contacts(read.contacts, written.has_contacts ? written.contacts : ContactRecords{});
}

// Two runs that must be the same (a resumed one against an uninterrupted one): every
// frame, and the rows and steps of the named observables.
inline void expect_same_run(const std::string& a_path, const std::string& b_path,
                            std::initializer_list<const char*> observables) {
  io::TrajectoryReader a(a_path), b(b_path);
  ASSERT_EQ(a.frame_count(), b.frame_count());
  for (std::size_t k = 0; k < a.frame_count(); ++k) {
    SCOPED_TRACE("frame " + std::to_string(k));
    const io::Frame fa = a.frame(k), fb = b.frame(k);
    EXPECT_EQ(fa.step, fb.step);
    EXPECT_EQ(fa.time, fb.time);
    expect_same_grains(fa, fb);
    expect_same_contacts(fa.contacts, fb.contacts);
  }
  for (const char* name : observables) {
    EXPECT_EQ(a.observable_scalar(name), b.observable_scalar(name)) << name;
    EXPECT_EQ(a.observable_step(name), b.observable_step(name)) << name;
  }
}

}  // namespace granflow::test_support
