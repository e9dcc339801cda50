// `diagnose --batch` and `twin --batch` default by device (diagnose/auto_batch.h): one run per process on a
// CPU device (lavapipe), ensembles of kGpuAutoBatch on a GPU. An explicit --batch is kept as given and never
// looks up a device; a device that does not exist is an error naming it.
#include <gtest/gtest.h>

#include <string>

#include "diagnose/auto_batch.h"
#include "vk/context.h"

using namespace wetdem::diagnose;

TEST(DiagnoseAutoBatch, AnExplicitBatchIsKeptWithoutLookingUpTheDevice) {
  std::string why;
  // No device of this name exists: looking one up would throw.
  EXPECT_EQ(resolve_batch(3, "no-such-device-xyz", &why), 3u);
  EXPECT_NE(why.find("3 runs per process (--batch)"), std::string::npos) << why;
  EXPECT_EQ(resolve_batch(1, "no-such-device-xyz", &why), 1u);
  EXPECT_NE(why.find("1 run per process"), std::string::npos) << why;
}

TEST(DiagnoseAutoBatch, OneRunPerProcessOnACpuDeviceEnsemblesOnAGpu) {
  std::string why;
  EXPECT_EQ(resolve_batch(0, "cpu", &why), 1u);
  EXPECT_NE(why.find("is a CPU device"), std::string::npos) << why;
  bool have_gpu = false;
  for (const std::string& d : wetdem::vk::Context::list_devices())
    have_gpu = have_gpu || d.find("GPU)") != std::string::npos;
  if (have_gpu) {
    EXPECT_EQ(resolve_batch(0, "gpu", &why), kGpuAutoBatch);
    EXPECT_NE(why.find("is a GPU"), std::string::npos) << why;
  } else {
    EXPECT_THROW(resolve_batch(0, "gpu", &why), std::runtime_error);  // "only CPU (lavapipe) devices"
  }
  try {
    resolve_batch(0, "no-such-device-xyz", &why);
    ADD_FAILURE() << "an unknown device must be an error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no-such-device-xyz"), std::string::npos) << e.what();
  }
}

// `diagnose` and `twin` resolve --batch and --jobs from one study::DeviceKind (one Vulkan context).
TEST(DiagnoseAutoBatch, SharesOneDeviceLookupWithJobs) {
  wetdem::study::DeviceKind kind("cpu");
  std::string why;
  EXPECT_EQ(resolve_batch(0, kind, &why), 1u);
  EXPECT_NE(why.find(kind.name()), std::string::npos) << why;
  EXPECT_GE(wetdem::study::resolve_jobs(0, kind), 1u);
}
