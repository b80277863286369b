#pragma once
/// Structured simplex meshes for tests that must not depend on Gmsh.
#include <cmath>
#include <map>
#include <vector>
#include <utility>

#include "fem/lagrange.hpp"
#include "fem/simplex.hpp"
#include "mesh/mesh.hpp"

namespace conserve::test {

/// [0,lx]×[0,ly]×[0,lz] split into n cubes per direction, 6 tets each
/// (facet group "xmin": the face x = 0).
inline mesh::Mesh box_mesh(int nx, int ny, int nz, double lx, double ly, double lz) {
  mesh::Mesh m;
  m.dim = 3;
  auto id = [&](int i, int j, int k) { return i + (nx + 1) * (j + (ny + 1) * k); };
  m.points.resize(3, (nx + 1) * (ny + 1) * (nz + 1));
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.points.col(id(i, j, k)) << lx * i / nx, ly * j / ny, lz * k / nz;
  const int tets[6][4] = {{0, 1, 3, 7}, {0, 3, 2, 7}, {0, 2, 6, 7}, {0, 6, 4, 7}, {0, 4, 5, 7}, {0, 5, 1, 7}};
  m.cells.resize(4, 6 * nx * ny * nz);
  int c = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& t : tets) {
          for (int a = 0; a < 4; ++a) m.cells(a, c) = id(i + (t[a] & 1), j + ((t[a] >> 1) & 1), k + ((t[a] >> 2) & 1));
          fem::NodeMatrix<3> X;
          for (int a = 0; a < 4; ++a) X.col(a) = m.points.col(m.cells(a, c));
          if (fem::signed_measure<3>(X) < 0) std::swap(m.cells(2, c), m.cells(3, c));
          ++c;
        }
  Eigen::MatrixXi xmin(3, 2 * ny * nz);
  int f = 0;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j) {
      xmin.col(f++) << id(0, j, k), id(0, j + 1, k + 1), id(0, j + 1, k);
      xmin.col(f++) << id(0, j, k), id(0, j, k + 1), id(0, j + 1, k + 1);
    }
  m.facet_groups["xmin"].facets = xmin;
  return m;
}

/// [0,lx]×[0,ly] split into n squares per direction, 2 triangles each.
inline mesh::Mesh rectangle_mesh(int nx, int ny, double lx, double ly) {
  mesh::Mesh m;
  m.dim = 2;
  auto id = [&](int i, int j) { return i + (nx + 1) * j; };
  m.points.resize(2, (nx + 1) * (ny + 1));
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) m.points.col(id(i, j)) << lx * i / nx, ly * j / ny;
  m.cells.resize(3, 2 * nx * ny);
  int c = 0;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      m.cells.col(c++) << id(i, j), id(i + 1, j), id(i + 1, j + 1);
      m.cells.col(c++) << id(i, j), id(i + 1, j + 1), id(i, j + 1);
    }
  Eigen::MatrixXi xmin(2, ny);
  for (int j = 0; j < ny; ++j) xmin.col(j) << id(0, j + 1), id(0, j);
  m.facet_groups["xmin"].facets = xmin;
  return m;
}

/// The linear mesh m with a node at the middle of every edge (Gmsh's order,
/// fem/lagrange.hpp), each moved by `bend` × (the edge's length) × a smooth
/// function of its position, so that cells are curved but keep positive
/// Jacobians for small `bend`. Facet groups become quadratic facets.
inline mesh::Mesh quadratic_mesh(const mesh::Mesh& m, double bend = 0.0) {
  const int dim = m.dim;
  std::map<std::pair<int, int>, int> middle;
  std::vector<Eigen::VectorXd> added;
  const auto node_of = [&](int a, int b) {
    const auto key = std::minmax(a, b);
    const auto [it, inserted] = middle.try_emplace({key.first, key.second}, m.num_nodes() + static_cast<int>(added.size()));
    if (inserted) {
      Eigen::VectorXd x = 0.5 * (m.points.col(a) + m.points.col(b));
      const double length = (m.points.col(a) - m.points.col(b)).norm();
      for (int i = 0; i < dim; ++i) x(i) += bend * length * std::sin(3.0 * x((i + 1) % dim) + i);
      added.push_back(x);
    }
    return it->second;
  };
  const auto edges2 = fem::Lagrange<2, 2>::edges();
  const auto edges3 = fem::Lagrange<3, 2>::edges();
  mesh::Mesh q;
  q.dim = dim;
  q.cell_groups = m.cell_groups;
  q.cells.resize(dim == 2 ? 6 : 10, m.num_cells());
  for (int c = 0; c < m.num_cells(); ++c) {
    q.cells.col(c).head(dim + 1) = m.cells.col(c);
    int e = dim + 1;
    if (dim == 2)
      for (const auto& [a, b] : edges2) q.cells(e++, c) = node_of(m.cells(a, c), m.cells(b, c));
    else
      for (const auto& [a, b] : edges3) q.cells(e++, c) = node_of(m.cells(a, c), m.cells(b, c));
  }
  for (const auto& [name, group] : m.facet_groups) {
    const Eigen::MatrixXi& f = group.facets;
    Eigen::MatrixXi out(dim == 2 ? 3 : 6, f.cols());
    for (Eigen::Index k = 0; k < f.cols(); ++k) {
      out.col(k).head(dim) = f.col(k);
      if (dim == 2) {
        out(2, k) = node_of(f(0, k), f(1, k));
      } else {
        out(3, k) = node_of(f(0, k), f(1, k)), out(4, k) = node_of(f(1, k), f(2, k)), out(5, k) = node_of(f(2, k), f(0, k));
      }
    }
    q.facet_groups[name].facets = out;
  }
  q.points.resize(dim, m.num_nodes() + static_cast<Eigen::Index>(added.size()));
  q.points.leftCols(m.num_nodes()) = m.points;
  for (std::size_t i = 0; i < added.size(); ++i) q.points.col(m.num_nodes() + static_cast<Eigen::Index>(i)) = added[i];
  return q;
}

}  // namespace conserve::test
