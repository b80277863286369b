#pragma once
/// Internal to the generators: meshes an OpenCASCADE geometry with the Gmsh
/// C++ API and turns the result into a Mesh.
#include <Eigen/Core>
#include <functional>
#include <mutex>
#include <string>

#include "mesh/mesh.hpp"

namespace conserve::mesh::detail {

/// A boundary entity (surface in 3D, curve in 2D) of the Gmsh model, in the
/// model's (normalised) coordinates.
struct EntityShape {
  Eigen::Vector3d centre;  ///< centre of mass
  Eigen::Vector3d lo, hi;  ///< bounding box (may be slightly enlarged by OCC)
};

/// What to mesh and how.
struct GmshRecipe {
  std::string name;  ///< generator name, for messages
  int dim = 3;
  /// Adds the OpenCASCADE entities to the (empty, current) model.
  std::function<void()> build;
  /// Facet group of a boundary entity ("" = only in "boundary").
  std::function<std::string(const EntityShape&)> classify;
  double size = 1.0;   ///< target element size, in model coordinates
  double scale = 1.0;  ///< model coordinates × scale = mesh coordinates [m]
  /// Element order: 1 (3-node triangles, 4-node tets) or 2 (6-node
  /// triangles, 10-node tets whose boundary midside nodes lie on the
  /// geometry, interior ones moved where needed to keep det J > 0).
  int order = 1;
};

/// One use of Gmsh, which is a global singleton: holds a process-wide lock
/// for its lifetime (uses are serialised), starts Gmsh quietly and finalises
/// it. Gmsh sets OpenMP's process-wide thread count to its
/// General.NumThreads (1) as it starts and meshes; the session puts back
/// what the process had, or every later parallel loop (the assembly) runs
/// on one thread.
class GmshSession {
 public:
  GmshSession();
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

 private:
  std::unique_lock<std::mutex> lock_;
  int threads_ = 1;
};

/// Meshes the recipe (serialised: Gmsh is a global singleton). The result has
/// cell group "body", facet group "boundary" and the named facet groups, all
/// facets outward oriented and all cells positively oriented (quadratic
/// ones also not folded, topology.hpp). Throws InputError if Gmsh fails.
Mesh mesh_with_gmsh(const GmshRecipe& recipe);

}  // namespace conserve::mesh::detail
