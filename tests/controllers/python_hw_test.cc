// The Python posture controller (python/examples/posture.py, through python/ohrp and the C
// API), unchanged, on the hardware path: hw_emulator <- UDP -> hw_driver <- segment -> Python.
// The same program stands HRP-1S on sim_host in scenario_stand_python. Skipped when the
// hardware programs are not built. Bounds are generous in wall time: the machine may be loaded.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "hw_chain.h"

namespace ohrp::controllers::testing {
namespace {

const std::string kPython = std::string(OHRP_SOURCE_DIR) + "/python/examples/posture.py";

TEST(PythonHw, PostureStandsThroughHwDriverAndUdp) {
  if (const std::string p = MissingHwProgram(kPython); !p.empty())
    GTEST_SKIP() << p << " is not built";
#ifdef OHRP_SANITIZE
  GTEST_SKIP() << "Python cannot load the ASan-built C library without LD_PRELOAD of the ASan "
                  "runtime; python_ohrp_test and scenario_stand_python run it that way";
#endif
  setenv("OHRP_LIB", OHRP_SHM_C_LIB, 1);  // this build's C library, whatever its folder
  const Chain c = RunChain("py_hw", {kPython, "--ramp", "2.0"}, {}, 6.0);
  ASSERT_EQ(c.driver, 0) << Diagnosis(c);
  ASSERT_EQ(c.controller, 0) << Diagnosis(c);
  EXPECT_EQ(c.emulator, 130) << Diagnosis(c);
  ASSERT_FALSE(c.summary.is_discarded()) << Diagnosis(c);
  EXPECT_EQ(c.summary["rejected_commands"], 0) << Diagnosis(c);
  // ramped to half-sitting by 2 s: within 2 cm of the keyframe's height, upright, steady
  const auto s = Span(c, 3.0, 5.9);
  EXPECT_NEAR(s[0], kHalfSitHeight, 0.02);
  EXPECT_LT(s[1] - s[0], 0.003);
  EXPECT_LT(s[2], 3.0);
  std::printf("[ figures  ] Python posture on hw_driver + udp + hw_emulator: base z %.4f..%.4f m, "
              "tilt max %.2f deg in [3, 5.9] s; driver: %s late commands\n%s",
              s[0], s[1], s[2], c.summary["late_commands"].dump().c_str(),
              c.controller_out.c_str());
}

}  // namespace
}  // namespace ohrp::controllers::testing
