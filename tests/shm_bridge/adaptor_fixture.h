// The robot adaptor tests' fixture: a segment name unique to the test, removed before and
// after it, a producer on it with the small three-joint configuration (test_util.h), and the
// data of each cycle. Used by adaptor_test.cc, adaptor_slot_test.cc and adaptor_cycle_test.cc.
#pragma once

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <string>

#include "shm_bridge/bridge.h"
#include "test_util.h"

namespace ohrp::shm::testing {

class AdaptorTest : public ::testing::Test {
 protected:
  void SetUp() override {
    name_ = testing::UniqueSegment(::testing::UnitTest::GetInstance()->current_test_info()->name());
    testing::RemoveSegment(name_);  // leftovers of an earlier crashed run
  }
  void TearDown() override { testing::RemoveSegment(name_); }

  std::unique_ptr<Producer> Create() {
    Status status;
    auto p = Producer::Create(testing::SmallConfig(name_), &status);
    EXPECT_TRUE(status.ok()) << status.message;
    return p;
  }

  static bool Contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
  }

  std::string name_;
};

// the data of cycle k: values that differ per cycle and per joint
inline double SensorValue(uint64_t k, int j) { return 1000.0 * static_cast<double>(k) + j + 0.25; }
inline double CommandValue(uint64_t k, int j) { return -SensorValue(k, j); }

}  // namespace ohrp::shm::testing
