// [body.rotate] (issue 52): a body placed at an angle, turned about the
// origin of its mesh's coordinates before `translate`; bad rotations are
// refused naming the key.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "core/error.hpp"
#include "io/scenario.hpp"
#include "simulation/setup.hpp"

namespace conserve::simulation {
namespace {

std::string box(const std::string& placement) {
  return "[time]\nstep = 0.01\nend = 0.1\n[[body]]\nname = \"a\"\n" + placement +
         "[body.material]\nyoung = 1e6\npoisson = 0.3\ndensity = 1000\n"
         "[body.mesh]\ngenerator = \"box\"\nlx = 1.0\nly = 0.5\nlz = 0.2\nsize = 0.25\n";
}

std::string rectangle(const std::string& placement) {
  return "dimension = 2\n[time]\nstep = 0.01\nend = 0.1\n[[body]]\nname = \"a\"\n" + placement +
         "[body.material]\nyoung = 1e6\npoisson = 0.3\ndensity = 1000\n"
         "[body.mesh]\ngenerator = \"rectangle\"\nlx = 1.0\nly = 0.5\nsize = 0.25\n";
}

template <int D>
Eigen::MatrixXd nodes(const std::string& text) {
  return setup<D>(io::parse_scenario(text, "case.toml")).model.X;
}

TEST(Rotate, TurnsAboutTheOriginBeforeTranslate3d) {
  const Eigen::MatrixXd plain = nodes<3>(box(""));
  const Eigen::MatrixXd turned =
      nodes<3>(box("translate = [1.0, 2.0, 3.0]\nrotate = {axis = [0.0, 1.0, 0.0], degrees = 30.0}\n"));
  const Eigen::Matrix3d R = Eigen::AngleAxisd(std::numbers::pi / 6, Eigen::Vector3d::UnitY()).toRotationMatrix();
  ASSERT_EQ(plain.cols(), turned.cols());
  const Eigen::MatrixXd expected = (R * plain).colwise() + Eigen::Vector3d(1.0, 2.0, 3.0);
  EXPECT_LT((turned - expected).cwiseAbs().maxCoeff(), 1e-14);
  // The matrix form of the same rotation places the same nodes.
  char text[512];
  std::snprintf(text, sizeof text, "rotate = {matrix = [[%.17g, %.17g, %.17g], [%.17g, %.17g, %.17g], [%.17g, %.17g, %.17g]]}\n",
                R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1), R(2, 2));
  const Eigen::MatrixXd by_matrix = nodes<3>(box(text));
  EXPECT_LT((by_matrix - R * plain).cwiseAbs().maxCoeff(), 1e-14);
}

TEST(Rotate, AboutZIn2d) {
  const Eigen::MatrixXd plain = nodes<2>(rectangle(""));
  const Eigen::MatrixXd turned = nodes<2>(rectangle("rotate = {degrees = 90.0}\n"));
  Eigen::Matrix2d R;
  R << 0.0, -1.0, 1.0, 0.0;
  EXPECT_LT((turned - R * plain).cwiseAbs().maxCoeff(), 1e-15);
}

/// The InputError message of setting up `text` ("" if none).
template <int D>
std::string error_of(const std::string& text) {
  try {
    nodes<D>(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Rotate, BadRotationsAreRefusedNamingTheKey) {
  const auto refused = [](const std::string& message, const std::string& key, const std::string& what) {
    EXPECT_NE(message.find(key), std::string::npos) << message;
    EXPECT_NE(message.find(what), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  };
  refused(error_of<3>(box("rotate = {degrees = 10.0}\n")), "body[0].rotate.axis", "missing key");
  refused(error_of<3>(box("rotate = {axis = [0.0, 0.0, 0.0], degrees = 10.0}\n")), "body[0].rotate.axis", "is zero");
  refused(error_of<3>(box("rotate = {axis = [0.0, 0.0, 1.0]}\n")), "body[0].rotate", "neither");
  refused(error_of<3>(box("rotate = {degrees = 10.0, matrix = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]}\n")),
          "body[0].rotate", "both");
  refused(error_of<3>(box("rotate = {matrix = [[1, 0, 0], [0, 1, 0], [0, 0, -1]]}\n")), "body[0].rotate.matrix",
          "not a rotation");
  refused(error_of<3>(box("rotate = {matrix = [[1, 0.1, 0], [0, 1, 0], [0, 0, 1]]}\n")), "body[0].rotate.matrix",
          "not a rotation");
  refused(error_of<2>(rectangle("rotate = {axis = [0.0, 0.0, 1.0], degrees = 10.0}\n")), "body[0].rotate.axis",
          "only meaningful in 3D");
  refused(error_of<3>(box("rotate = {degrees = 10.0, axis = [0, 0, 1], turns = 2}\n")), "body[0].rotate.turns",
          "unknown key");
}

}  // namespace
}  // namespace conserve::simulation
