/// The scenario parser on valid input: every field, defaults, 2D.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "scenario_test_support.hpp"

namespace conserve::io {
namespace {

namespace fs = std::filesystem;
using cases::case_file;
using cases::minimal;
using cases::scenario_dir;

TEST(Scenario, Full3dScenarioParsesEveryField) {
  const auto file = fs::path(scenario_dir()) / "full_3d.toml";
  const auto s = read_scenario(file);
  EXPECT_EQ(s.file, file);
  EXPECT_EQ(s.title, "cube on a floor");
  EXPECT_EQ(s.dimension, 3);
  EXPECT_EQ(s.time.step, 1e-3);
  EXPECT_EQ(s.time.end, 0.5);
  EXPECT_EQ(s.time.scheme, StressScheme::midpoint);
  EXPECT_EQ(s.time.mass, MassKind::lumped);
  EXPECT_EQ(s.newton.max_iterations, 30);
  EXPECT_EQ(s.newton.residual_tolerance, 1e-10);
  EXPECT_EQ(s.gravity, Eigen::Vector3d(0, 0, -9.81));
  EXPECT_EQ(s.output.directory, fs::path("results/full"));
  EXPECT_EQ(s.output.vtu_every, 5);
  EXPECT_EQ(s.output.progress_every, 100);
  ASSERT_EQ(s.bodies.size(), 3u);
  ASSERT_EQ(s.boundaries.size(), 2u);
  EXPECT_FALSE(s.bodies[0].rigid);
  EXPECT_FALSE(s.bodies[1].rigid);
  EXPECT_EQ(s.active_set.max_passes, 4);
}

TEST(Scenario, Full3dRigidBody) {
  const auto s = read_scenario(fs::path(scenario_dir()) / "full_3d.toml");
  const auto& wall = s.bodies.at(2);
  EXPECT_EQ(wall.name, "wall");
  EXPECT_TRUE(wall.rigid);
  EXPECT_EQ(wall.velocity, Eigen::Vector3d(-0.5, 0, 0));
  EXPECT_EQ(wall.translate, Eigen::Vector3d(2, 0, 0));
  EXPECT_EQ(wall.material.density, 0.0);  // no material: left at zero
  EXPECT_EQ(wall.mesh.generator, "square");
  EXPECT_EQ(wall.mesh.parameters, (std::map<std::string, double>{{"lx", 1}, {"ly", 2}, {"size", 0.5}}));
}

TEST(Scenario, Full3dContacts) {
  const auto s = read_scenario(fs::path(scenario_dir()) / "full_3d.toml");
  ASSERT_EQ(s.contacts.size(), 2u);
  const auto& floor = s.contacts[0];
  EXPECT_EQ(floor.slave_body, "cube");
  EXPECT_EQ(floor.slave_group, "boundary");
  EXPECT_EQ(floor.master_body, "floor");
  EXPECT_EQ(floor.master_group, "top");
  EXPECT_EQ(floor.kind, ContactKind::frictionless);
  EXPECT_EQ(floor.depth_factor, 0.25);
  const auto& wall = s.contacts[1];
  EXPECT_EQ(wall.slave_body, "cube");
  EXPECT_EQ(wall.slave_group, "top");
  EXPECT_EQ(wall.master_body, "wall");
  EXPECT_EQ(wall.master_group, "boundary");
  EXPECT_EQ(wall.kind, ContactKind::stick);
  EXPECT_EQ(wall.depth_factor, 0.5);
}

TEST(Scenario, Full3dFirstBodyWithMeshFile) {
  const auto s = read_scenario(fs::path(scenario_dir()) / "full_3d.toml");
  const auto& b = s.bodies.at(0);
  EXPECT_EQ(b.name, "cube");
  EXPECT_EQ(b.translate, Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(b.velocity, Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(b.angular_velocity, Eigen::Vector3d(0.5, -1, 2));
  Eigen::Matrix3d f0;
  f0 << 1.1, 0, 0, 0, 0.95, 0, 0, 0.1, 1;
  EXPECT_EQ(b.initial_deformation, f0);
  EXPECT_EQ(b.thickness, 1.0);
  EXPECT_EQ(b.material.parameter("young"), 2.1e9);
  EXPECT_EQ(b.material.parameter("poisson"), 0.3);
  EXPECT_EQ(b.material.density, 2500.0);
  EXPECT_TRUE(b.mesh.file.is_absolute());
  EXPECT_TRUE(fs::equivalent(b.mesh.file, fs::path(scenario_dir()) / "meshes" / "cube.msh"));
  EXPECT_EQ(b.mesh.group, "cube");
  EXPECT_TRUE(b.mesh.generator.empty());
  EXPECT_TRUE(b.mesh.parameters.empty());
}

TEST(Scenario, Full3dSecondBodyWithGenerator) {
  const auto s = read_scenario(fs::path(scenario_dir()) / "full_3d.toml");
  const auto& b = s.bodies.at(1);
  EXPECT_EQ(b.name, "floor");
  EXPECT_EQ(b.material.parameter("young"), 2e11);
  EXPECT_EQ(b.material.parameter("poisson"), -0.25);
  EXPECT_EQ(b.material.density, 7800.0);
  EXPECT_TRUE(b.mesh.file.empty());
  EXPECT_TRUE(b.mesh.group.empty());
  EXPECT_EQ(b.mesh.generator, "plate");
  const std::map<std::string, double> parameters{{"lx", 4.0}, {"ly", 4.0}, {"thickness", 0.2}, {"size", 0.5}};
  EXPECT_EQ(b.mesh.parameters, parameters);
}

TEST(Scenario, Full3dBoundaries) {
  const auto s = read_scenario(fs::path(scenario_dir()) / "full_3d.toml");
  const auto& floor = s.boundaries.at(0);
  EXPECT_EQ(floor.body, "floor");
  EXPECT_EQ(floor.group, "bottom");
  EXPECT_EQ(floor.components, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(floor.value, Eigen::Vector3d::Zero());
  EXPECT_EQ(floor.rate, Eigen::Vector3d::Zero());
  const auto& top = s.boundaries.at(1);
  EXPECT_EQ(top.body, "cube");
  EXPECT_EQ(top.group, "top");
  EXPECT_EQ(top.components, (std::vector<int>{0, 2}));
  EXPECT_EQ(top.value, Eigen::Vector3d(0.1, 0, -0.2));
  EXPECT_EQ(top.rate, Eigen::Vector3d(0, 0.5, -1));
}

TEST(Scenario, DefaultsApplied) {
  const auto s = parse_scenario(minimal(), case_file());
  EXPECT_EQ(s.title, "");
  EXPECT_EQ(s.dimension, 3);
  EXPECT_EQ(s.time.step, 0.01);
  EXPECT_EQ(s.time.end, 0.1);
  EXPECT_EQ(s.time.scheme, StressScheme::conserving);
  EXPECT_EQ(s.time.mass, MassKind::consistent);
  EXPECT_EQ(s.newton.max_iterations, 20);
  EXPECT_EQ(s.newton.residual_tolerance, 1e-12);
  EXPECT_EQ(s.gravity, Eigen::Vector3d::Zero());
  EXPECT_EQ(s.output.directory, fs::path("out"));
  EXPECT_EQ(s.output.vtu_every, 10);
  EXPECT_EQ(s.output.progress_every, 0);
  EXPECT_TRUE(s.boundaries.empty());
  EXPECT_TRUE(s.contacts.empty());
  EXPECT_EQ(s.active_set.max_passes, 30);
  ASSERT_EQ(s.bodies.size(), 1u);
  const auto& b = s.bodies[0];
  EXPECT_FALSE(b.rigid);
  EXPECT_EQ(b.translate, Eigen::Vector3d::Zero());
  EXPECT_EQ(b.velocity, Eigen::Vector3d::Zero());
  EXPECT_EQ(b.angular_velocity, Eigen::Vector3d::Zero());
  EXPECT_EQ(b.initial_deformation, Eigen::Matrix3d::Identity());
  EXPECT_EQ(b.thickness, 1.0);
  EXPECT_TRUE(b.mesh.group.empty());
}

TEST(Scenario, DefaultsInPartialTables) {
  const auto s = parse_scenario(minimal("[newton]\nmax_iterations = 5\n[output]\nvtu_every = 0\n"), case_file());
  EXPECT_EQ(s.newton.max_iterations, 5);
  EXPECT_EQ(s.newton.residual_tolerance, 1e-12);
  EXPECT_EQ(s.output.vtu_every, 0);
  EXPECT_EQ(s.output.directory, fs::path("out"));
}

TEST(Scenario, BoundaryDefaults) {
  const auto s = parse_scenario(minimal("[[boundary]]\nbody = \"a\"\ngroup = \"all\"\n"), case_file());
  ASSERT_EQ(s.boundaries.size(), 1u);
  EXPECT_EQ(s.boundaries[0].components, (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(s.boundaries[0].value, Eigen::Vector3d::Zero());
  EXPECT_EQ(s.boundaries[0].rate, Eigen::Vector3d::Zero());
}

TEST(Scenario, TwoDimensionalScenario) {
  const auto s = read_scenario(fs::path(scenario_dir()) / "full_2d.toml");
  EXPECT_EQ(s.dimension, 2);
  EXPECT_EQ(s.time.end, 1.0);
  EXPECT_EQ(s.gravity, Eigen::Vector3d(0, -9.81, 0));
  ASSERT_EQ(s.bodies.size(), 3u);
  const auto& disc = s.bodies[0];
  EXPECT_EQ(disc.translate, Eigen::Vector3d(0.5, 2, 0));
  EXPECT_EQ(disc.velocity, Eigen::Vector3d(0, -1.5, 0));
  EXPECT_EQ(disc.angular_velocity, Eigen::Vector3d(0, 0, 3));
  Eigen::Matrix3d f0;
  f0 << 1.2, 0.1, 0, 0, 0.9, 0, 0, 0, 1;
  EXPECT_EQ(disc.initial_deformation, f0);
  EXPECT_EQ(disc.thickness, 0.05);
  EXPECT_TRUE(fs::equivalent(disc.mesh.file, fs::path(scenario_dir()) / "meshes" / "disc.msh"));
  const auto& block = s.bodies[1];
  EXPECT_EQ(block.thickness, 1.0);
  EXPECT_EQ(block.mesh.generator, "rectangle");
  EXPECT_EQ(block.mesh.parameters, (std::map<std::string, double>{{"lx", 2}, {"ly", 0.5}, {"size", 0.1}}));
  const auto& ground = s.bodies[2];
  EXPECT_TRUE(ground.rigid);
  EXPECT_EQ(ground.velocity, Eigen::Vector3d(0, 0.1, 0));
  EXPECT_EQ(ground.material.density, 2000.0);  // optional on a rigid body, but kept
  EXPECT_EQ(ground.mesh.generator, "segment");
  ASSERT_EQ(s.contacts.size(), 1u);
  EXPECT_EQ(s.contacts[0].slave_group, "rim");
  EXPECT_EQ(s.contacts[0].master_body, "ground");
}

TEST(Scenario, TwoDimensionalBoundaries) {
  const auto s = read_scenario(fs::path(scenario_dir()) / "full_2d.toml");
  ASSERT_EQ(s.boundaries.size(), 2u);
  EXPECT_EQ(s.boundaries[0].components, (std::vector<int>{0, 1}));
  EXPECT_EQ(s.boundaries[1].components, (std::vector<int>{1}));
  EXPECT_EQ(s.boundaries[1].rate, Eigen::Vector3d(0, -0.25, 0));
}

TEST(Scenario, AbsoluteMeshFileIsKept) {
  const auto mesh = (fs::path(scenario_dir()) / "meshes" / "cube.msh").lexically_normal();
  const auto text = cases::with_mesh("file = \"" + mesh.generic_string() + "\"\n");
  const auto s = parse_scenario(text, "/nonexistent/folder/x.toml");
  EXPECT_EQ(s.bodies[0].mesh.file, mesh);
}

TEST(Scenario, ReadScenarioMissingFileThrows) {
  const auto file = fs::path(scenario_dir()) / "does_not_exist.toml";
  try {
    read_scenario(file);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(file.string()), std::string::npos) << e.what();
  }
}

TEST(Scenario, GeneratorParametersTakenFromTheCatalog) {
  const auto text = cases::with_mesh("generator = \"box\"\nlx = 1\nly = 2\nlz = 3\nsize = 0.5\n");
  const auto s = parse_scenario(text, case_file());
  EXPECT_EQ(s.bodies[0].mesh.parameters,
            (std::map<std::string, double>{{"lx", 1}, {"ly", 2}, {"lz", 3}, {"size", 0.5}}));
}

}  // namespace
}  // namespace conserve::io
