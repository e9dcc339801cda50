// One process at a time plans into a run store (study::StoreLock): a second planner waits until the first
// has run its plan, instead of overwriting the index.json its run-one processes read by index (two diagnoses
// sharing --store once ran each other's runs and found their own "missing").
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <thread>

#include <unistd.h>

#include "study/store.h"

namespace wetdem::test {

TEST(StudyStore, ASecondPlannerWaitsForTheFirst) {
  const auto dir = std::filesystem::temp_directory_path() / ("wetdem-lock-" + std::to_string(::getpid()));
  std::atomic<bool> second_has_it{false};
  std::thread second;
  {
    const study::StoreLock first(dir.string());
    // flock locks belong to the open file: a second open in this process conflicts as another process would.
    second = std::thread([&] {
      const study::StoreLock lock(dir.string());
      second_has_it = true;
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    EXPECT_FALSE(second_has_it) << "the second planner did not wait";
  }
  second.join();
  EXPECT_TRUE(second_has_it) << "the second planner never got the store";
  std::filesystem::remove_all(dir);
}

}  // namespace wetdem::test
