/// Comparing a checkpoint's fingerprint with a scenario's: the first entry
/// that differs, named.
#include <gtest/gtest.h>

#include "simulation/fingerprint.hpp"

namespace conserve::simulation {
namespace {

const Fingerprint kWritten = {{"dimension", 1, "2"},
                              {"body 'ball' material", 2, "young 1 Pa"},
                              {"body 'ball' node coordinates", 3, ""},
                              {"[time] step", 4, "0.001"}};

Fingerprint with(std::size_t i, FingerprintEntry e) {
  Fingerprint f = kWritten;
  f[i] = std::move(e);
  return f;
}

TEST(Fingerprint, EqualFingerprintsHaveNoDifference) { EXPECT_EQ(first_difference(kWritten, kWritten), ""); }

TEST(Fingerprint, NamesTheFirstEntryThatDiffers) {
  Fingerprint now = with(3, {"[time] step", 5, "0.002"});
  now[1] = {"body 'ball' material", 6, "young 2 Pa"};
  EXPECT_EQ(first_difference(kWritten, now),
            "the checkpoint was written with body 'ball' material = young 1 Pa, this scenario has young 2 Pa");
  EXPECT_EQ(first_difference(kWritten, with(3, {"[time] step", 5, "0.002"})),
            "the checkpoint was written with [time] step = 0.001, this scenario has 0.002");
}

TEST(Fingerprint, BulkDataOnlySaysItDiffers) {
  EXPECT_EQ(first_difference(kWritten, with(2, {"body 'ball' node coordinates", 9, ""})),
            "body 'ball' node coordinates differ");
  // equal printable values but another hash: no "a = x, this scenario has x"
  EXPECT_EQ(first_difference(kWritten, with(1, {"body 'ball' material", 9, "young 1 Pa"})),
            "body 'ball' material differs");
}

TEST(Fingerprint, EntriesMissingOnEitherSide) {
  Fingerprint fewer = kWritten;
  fewer.pop_back();
  EXPECT_EQ(first_difference(kWritten, fewer), "[time] step is not in this scenario");
  EXPECT_EQ(first_difference(fewer, kWritten), "[time] step is not in the checkpoint");
}

TEST(Fingerprint, ANumberingByOtherRanksGraphPartsNamesBothCounts) {
  // Written on 2 ranks whose graph parts numbered the nodes; read here by
  // one process (solver::ranks::size() == 1), which numbers as the meshes.
  Fingerprint by_parts = kWritten;
  by_parts.insert(by_parts.begin(), {"node numbering", 1, "2"});
  const std::string refused = first_difference(by_parts, kWritten);
  EXPECT_NE(refused.find("written on 2 ranks"), std::string::npos) << refused;
  EXPECT_NE(refused.find("this run has 1 rank"), std::string::npos) << refused;
  EXPECT_NE(first_difference(kWritten, by_parts).find("partition = \"ranges\""), std::string::npos);
  Fingerprint three = by_parts;
  three.front().value = "3";
  three.front().hash = 2;
  EXPECT_NE(first_difference(by_parts, three).find("restart on 2 ranks"), std::string::npos);
  EXPECT_EQ(first_difference(by_parts, by_parts), "");
}

}  // namespace
}  // namespace conserve::simulation
