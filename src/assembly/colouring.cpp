#include "assembly/colouring.hpp"

#include <algorithm>
#include <numeric>

namespace conserve::assembly {
namespace {

constexpr int kMaxChunk = 512;
constexpr int kChunksPerColour = 16;

/// Node → chunks in compressed rows: the chunks touching node n, ascending
/// and distinct, are chunk_of[first[n] .. first[n+1]).
struct NodeChunks {
  std::vector<int> first;
  std::vector<int> chunk_of;
};

NodeChunks node_chunks(int num_nodes, const Eigen::MatrixXi& cells, int chunk_size) {
  std::vector<int> last(num_nodes, -1);  // last chunk seen at each node
  NodeChunks nc{std::vector<int>(num_nodes + 1, 0), {}};
  for (int c = 0; c < cells.cols(); ++c)
    for (int a = 0; a < cells.rows(); ++a) {
      const int n = cells(a, c);
      if (last[n] != c / chunk_size) ++nc.first[n + 1], last[n] = c / chunk_size;
    }
  std::partial_sum(nc.first.begin(), nc.first.end(), nc.first.begin());
  nc.chunk_of.resize(nc.first.back());
  std::vector<int> next(nc.first.begin(), nc.first.end() - 1);
  std::fill(last.begin(), last.end(), -1);
  for (int c = 0; c < cells.cols(); ++c)
    for (int a = 0; a < cells.rows(); ++a) {
      const int n = cells(a, c);
      if (last[n] != c / chunk_size) nc.chunk_of[next[n]++] = last[n] = c / chunk_size;
    }
  return nc;
}

/// Calls visit(r) for every chunk r that shares a node with chunk q (q
/// itself included, a chunk possibly more than once).
template <class Visit>
void for_each_neighbour(const NodeChunks& nc, const Eigen::MatrixXi& cells, int chunk_size, int q, const Visit& visit) {
  const int end = std::min(static_cast<int>(cells.cols()), (q + 1) * chunk_size);
  for (int c = q * chunk_size; c < end; ++c)
    for (int a = 0; a < cells.rows(); ++a)
      for (int j = nc.first[cells(a, c)]; j < nc.first[cells(a, c) + 1]; ++j) visit(nc.chunk_of[j]);
}

/// Lowest colour not taken by an earlier neighbour, per chunk.
std::vector<int> greedy_colours(const NodeChunks& nc, const Eigen::MatrixXi& cells, int chunk_size, int num_chunks) {
  std::vector<int> colour(num_chunks, -1);
  std::vector<int> taken_by;  // taken_by[k] == q: an earlier neighbour of chunk q has colour k
  for (int q = 0; q < num_chunks; ++q) {
    for_each_neighbour(nc, cells, chunk_size, q, [&](int r) {
      if (r < q) taken_by[colour[r]] = q;
    });
    int k = 0;
    while (k < static_cast<int>(taken_by.size()) && taken_by[k] == q) ++k;
    if (k == static_cast<int>(taken_by.size())) taken_by.push_back(-1);
    colour[q] = k;
  }
  return colour;
}

}  // namespace

CellColouring colour_cells(int num_nodes, const Eigen::MatrixXi& cells, int chunk_size) {
  const int num_cells = static_cast<int>(cells.cols());
  const int num_chunks = (num_cells + chunk_size - 1) / chunk_size;
  const NodeChunks nc = node_chunks(num_nodes, cells, chunk_size);
  const std::vector<int> colour = greedy_colours(nc, cells, chunk_size, num_chunks);
  const int num_colours = num_chunks ? *std::max_element(colour.begin(), colour.end()) + 1 : 0;
  CellColouring result{chunk_size, num_cells, std::vector<int>(num_colours + 1, 0), std::vector<int>(num_chunks),
                       {0},        {}};
  for (int q = 0; q < num_chunks; ++q) ++result.start[colour[q] + 1];
  std::partial_sum(result.start.begin(), result.start.end(), result.start.begin());
  std::vector<int> next(result.start.begin(), result.start.end() - 1);
  for (int q = 0; q < num_chunks; ++q) result.chunks[next[colour[q]]++] = q;
  std::vector<int> position(num_chunks);  // chunk → index in result.chunks
  for (int j = 0; j < num_chunks; ++j) position[result.chunks[j]] = j;
  std::vector<int> seen(num_chunks, -1);
  for (int j = 0; j < num_chunks; ++j) {
    const int q = result.chunks[j];
    for_each_neighbour(nc, cells, chunk_size, q, [&](int r) {
      if (colour[r] < colour[q] && seen[r] != q) seen[r] = q, result.waits_for.push_back(position[r]);
    });
    result.wait_start.push_back(static_cast<int>(result.waits_for.size()));
  }
  return result;
}

CellColouring colour_cells(int num_nodes, const Eigen::MatrixXi& cells) {
  for (int chunk = kMaxChunk;; chunk /= 2) {
    CellColouring colouring = colour_cells(num_nodes, cells, chunk);
    if (chunk == 1 || colouring.chunks.size() >= static_cast<std::size_t>(kChunksPerColour) * colouring.num_colours())
      return colouring;
  }
}

}  // namespace conserve::assembly
