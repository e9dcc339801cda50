// `--jobs`' default by device (study/parallel.h), for study run, diagnose and twin: one process per core on a
// CPU device, up to kCpuAutoJobsMax; one on a GPU. An explicit --jobs never looks up a device.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <thread>

#include "study/parallel.h"

using namespace wetdem::study;

TEST(StudyParallel, OneJobPerCoreOnACpuDeviceOneOnAGpu) {
  EXPECT_EQ(auto_jobs(true, 2), 2u);
  EXPECT_EQ(auto_jobs(true, 1), 1u);
  EXPECT_EQ(auto_jobs(true, 0), 1u) << "cores unknown";
  EXPECT_EQ(auto_jobs(true, 64), kCpuAutoJobsMax);
  EXPECT_EQ(auto_jobs(false, 16), 1u);
  std::string why;
  EXPECT_EQ(resolve_jobs(3, "no-such-device-xyz", &why), 3u) << "an explicit --jobs looks nothing up";
  EXPECT_NE(why.find("3 runs at a time (--jobs)"), std::string::npos) << why;
  const size_t k = resolve_jobs(0, "cpu", &why);
  EXPECT_GE(k, 1u);
  EXPECT_LE(k, kCpuAutoJobsMax);
  EXPECT_NE(why.find("(auto: one per CPU core"), std::string::npos) << why;
  EXPECT_THROW(resolve_jobs(0, "no-such-device-xyz", &why), std::runtime_error);
}

// The device is looked up once, when a default first needs it, and never for explicit values.
TEST(StudyParallel, DeviceKindIsLearntOnFirstUse) {
  DeviceKind missing("no-such-device-xyz");
  EXPECT_EQ(resolve_jobs(2, missing), 2u) << "an explicit --jobs looks nothing up";
  EXPECT_THROW(missing.cpu(), std::runtime_error);
  DeviceKind cpu("cpu");
  EXPECT_TRUE(cpu.cpu());
  EXPECT_FALSE(cpu.name().empty());
  std::string why;
  EXPECT_EQ(resolve_jobs(0, cpu, &why), auto_jobs(true, std::thread::hardware_concurrency()));
  EXPECT_NE(why.find("(auto: one per CPU core"), std::string::npos) << why;
}
