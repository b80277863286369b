// Garbage in: parse_msh must only ever throw InputError (no crash, no hang,
// no other exception) on random bytes and on mutated or cut valid files,
// volume meshes and bare surfaces alike.
#include <gtest/gtest.h>

#include <random>

#include "core/error.hpp"
#include "mesh/msh_reader.hpp"
#include "mesh_checks.hpp"
#include "msh_samples.hpp"

namespace conserve::mesh {
namespace {

/// Parses; returns false (and records a failure) on anything but success or InputError.
bool parses_or_input_error(const std::string& bytes, int dim, BareSurface bare = BareSurface::rejected) {
  try {
    parse_msh(bytes, "fuzz.msh", dim, bare);
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    ADD_FAILURE() << "unexpected exception: " << e.what();
    return false;
  } catch (...) {
    ADD_FAILURE() << "unexpected non-std exception";
    return false;
  }
  return true;
}

std::string random_bytes(std::mt19937& rng, std::size_t n, bool text) {
  static const std::string alphabet = "0123456789 \n.-e$\"EndNodesElementsMeshFormat";
  std::string out(n, '\0');
  for (char& c : out) c = text ? alphabet[rng() % alphabet.size()] : static_cast<char>(rng() % 256);
  return out;
}

/// `valid` with a few bytes changed, inserted or removed, or cut short.
std::string mutate(std::mt19937& rng, std::string s) {
  const int edits = 1 + static_cast<int>(rng() % 4);
  for (int e = 0; e < edits && !s.empty(); ++e) {
    const std::size_t at = rng() % s.size();
    switch (rng() % 5) {
      case 0:
        s[at] = static_cast<char>(rng() % 256);
        break;
      case 1:
        s[at] = "0123456789-"[rng() % 11];
        break;
      case 2:
        s.insert(at, std::to_string(rng()));
        break;
      case 3:
        s.erase(at, 1 + rng() % 8);
        break;
      default:
        s.resize(at);
        break;
    }
  }
  return s;
}

TEST(MshFuzz, RandomBytesOnlyThrowInputError) {
  std::mt19937 rng(12345);
  const std::string header = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  for (int i = 0; i < 2000; ++i) {
    const std::size_t n = rng() % 300;
    const bool text = i % 2 == 0;
    const std::string prefix = i % 3 == 0 ? header : (i % 3 == 1 ? header + "$Nodes\n" : "");
    ASSERT_TRUE(parses_or_input_error(prefix + random_bytes(rng, n, text), 2 + i % 2)) << i;
  }
}

TEST(MshFuzz, MutatedValidFilesOnlyThrowInputError) {
  std::mt19937 rng(777);
  const std::vector<std::pair<std::string, int>> valid = {
      {test::file_bytes(test::data_dir() / "cube_ascii.msh"), 3},
      {test::file_bytes(test::data_dir() / "cube_binary.msh"), 3},
      {test::file_bytes(test::data_dir() / "square.msh"), 2},
      {test::kTinyTet, 3},
      {test::kTinySquare2D, 2},
      {test::kGmshTet10, 3},
      {test::kGmshSquareTri6, 2},
  };
  for (int i = 0; i < 3000; ++i) {
    const auto& [bytes, dim] = valid[static_cast<std::size_t>(i) % valid.size()];
    ASSERT_TRUE(parses_or_input_error(mutate(rng, bytes), dim)) << i;
  }
}

TEST(MshFuzz, MutatedSurfaceFilesOnlyThrowInputError) {
  std::mt19937 rng(4242);
  const std::vector<std::pair<std::string, int>> valid = {
      {test::file_bytes(test::data_dir() / "tray.msh"), 3},
      {test::file_bytes(test::data_dir() / "valley.msh"), 2},
      {test::kTinySurface, 3},
      {test::kTinyLine2D, 2},
  };
  for (int i = 0; i < 3000; ++i) {
    const auto& [bytes, dim] = valid[static_cast<std::size_t>(i) % valid.size()];
    ASSERT_TRUE(parses_or_input_error(mutate(rng, bytes), dim, BareSurface::accepted)) << i;
  }
}

}  // namespace
}  // namespace conserve::mesh
