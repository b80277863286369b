// The contact-state VTU: written atomically, with the documented fields.
#include <gtest/gtest.h>

#include <filesystem>

#include "contact/debug_output.hpp"
#include "core/error.hpp"
#include "support/files.hpp"

namespace conserve::contact {
namespace {

namespace fs = std::filesystem;

template <int D>
void writes_fields(const std::string& name) {
  const auto dir = test::scratch("contact_" + name);
  Positions<D> x = Positions<D>::Zero(D, 4);
  x(0, 1) = 1.0;
  x(1, 2) = 1.0;
  x(0, 3) = 2.0;
  FacetNodes<D> master = FacetNodes<D>::Identity();
  Match<D> hit{5, project<D>(x.col(1), master)};
  const std::vector<std::optional<Match<D>>> matches{hit, std::nullopt, hit};
  const auto file = dir / "contact.vtu";
  write_contact_state_vtu<D>(file, {1, 2, 3}, x, matches);
  ASSERT_TRUE(fs::exists(file));
  const std::string xml = test::slurp(file);
  EXPECT_NE(xml.find("<VTKFile"), std::string::npos);
  EXPECT_NE(xml.find("NumberOfPoints=\"3\""), std::string::npos);
  for (const char* field : {"gap", "normal", "master_facet", "xi", "inside", "slave_node"})
    EXPECT_NE(xml.find(std::string("Name=\"") + field + "\""), std::string::npos) << field;
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().filename(), "contact.vtu") << "left behind: " << entry.path();
  EXPECT_THROW(write_contact_state_vtu<D>(file, {1, 2}, x, matches), Error);
  EXPECT_THROW(write_contact_state_vtu<D>(file, {1, 2, 9}, x, matches), Error);
}

TEST(DebugOutput, ContactState3d) { writes_fields<3>("state3"); }
TEST(DebugOutput, ContactState2d) { writes_fields<2>("state2"); }

TEST(DebugOutput, NoSlavesStillWritesAValidFile) {
  const auto dir = test::scratch("contact_empty");
  write_contact_state_vtu<3>(dir / "none.vtu", {}, Positions<3>::Zero(3, 2), {});
  EXPECT_TRUE(fs::exists(dir / "none.vtu"));
}

}  // namespace
}  // namespace conserve::contact
