#pragma once
/// Shared helpers of the contact tests: one-body models and surfaces.
#include <string>

#include "material/svk_law.hpp"
#include "contact/surface.hpp"
#include "model/model.hpp"

namespace conserve::test {

/// A model holding `mesh` as its only body, named `name`.
template <int D>
model::Model<D> one_body_model(const mesh::Mesh& mesh, const std::string& name = "body") {
  model::Model<D> model;
  model::add_body<D>(model, mesh, name, std::make_shared<const material::Svk>(material::Lame{1.0, 1.0}), 1.0, 1.0);
  return model;
}

/// Volume (3D) or area (2D) enclosed by a closed surface, by the divergence
/// theorem: (1/D) Σ_f (centroid_f · n_f) |f|. Positive iff the facets face out.
template <int D>
double enclosed_measure(const contact::ContactSurface& surface, const Eigen::Matrix<double, D, Eigen::Dynamic>& x) {
  double sum = 0.0;
  for (int f = 0; f < surface.num_facets(); ++f) {
    Eigen::Matrix<double, D, D> p;
    for (int i = 0; i < D; ++i) p.col(i) = x.col(surface.facets(i, f));
    const Eigen::Matrix<double, D, 1> centroid = p.rowwise().mean();
    Eigen::Matrix<double, D, 1> area_normal;  // |f| n
    if constexpr (D == 3)
      area_normal = 0.5 * (p.col(1) - p.col(0)).cross(p.col(2) - p.col(0));
    else
      area_normal << p(1, 1) - p(1, 0), -(p(0, 1) - p(0, 0));
    sum += centroid.dot(area_normal);
  }
  return sum / D;
}

}  // namespace conserve::test
