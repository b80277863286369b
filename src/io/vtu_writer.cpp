/// VTK XML UnstructuredGrid (appended raw binary, optionally zlib-compressed
/// blocks, UInt64 headers) and PVD.
#include "io/vtu_writer.hpp"

#include <fstream>

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>

#include <zlib.h>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace conserve::io {
namespace {

constexpr std::string_view byte_order = std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";
/// Uncompressed bytes per zlib block (VTK's own writer's default).
constexpr std::size_t kBlockSize = 32768;

/// The arrays of one file: the XML that names them and the appended data
/// they point into (each array: its UInt64 header, then its bytes).
class Arrays {
 public:
  explicit Arrays(const VtuFormat& format) : format_(format) {}

  template <typename T>
  std::string add(std::string_view type, std::string_view name, int components, const std::vector<T>& values,
                  const std::vector<std::string>& component_names = {}) {
    std::string attributes = name.empty() ? std::string() : fmt::format(" Name=\"{}\"", detail::xml_escape(name));
    for (std::size_t c = 0; c < component_names.size(); ++c)
      attributes += fmt::format(" ComponentName{}=\"{}\"", c, detail::xml_escape(component_names[c]));
    const std::string element =
        fmt::format("        <DataArray type=\"{}\"{} NumberOfComponents=\"{}\" format=\"appended\" offset=\"{}\"/>\n",
                    type, attributes, components, data_.size());
    append(reinterpret_cast<const unsigned char*>(values.data()), values.size() * sizeof(T));
    return element;
  }

  /// A field of doubles, as Float32 when the format asks for it.
  std::string add_field(const VtuField& field) {
    if (!format_.single_precision)
      return add("Float64", field.name, field.components, field.values, field.component_names);
    const std::vector<float> single(field.values.begin(), field.values.end());
    return add("Float32", field.name, field.components, single, field.component_names);
  }

  [[nodiscard]] const std::string& data() const { return data_; }
  [[nodiscard]] const VtuFormat& format() const { return format_; }

 private:
  template <typename T>
  void put(T value) {
    data_.append(reinterpret_cast<const char*>(&value), sizeof value);
  }

  // Raw: [byte count] bytes. Compressed (VTK's block layout): [blocks,
  // block size, last block's size, each block's compressed size] and the
  // compressed blocks.
  void append(const unsigned char* bytes, std::size_t size) {
    if (!format_.compress) {
      put<std::uint64_t>(size);
      if (size > 0) data_.append(reinterpret_cast<const char*>(bytes), size);
      return;
    }
    const std::size_t blocks = (size + kBlockSize - 1) / kBlockSize;
    put<std::uint64_t>(blocks);
    put<std::uint64_t>(kBlockSize);
    put<std::uint64_t>(blocks == 0 ? 0 : size - (blocks - 1) * kBlockSize);
    // The blocks are independent: compressed on the OpenMP threads.
    std::vector<std::vector<unsigned char>> out(blocks);
    std::vector<int> failed(blocks, 0);
#pragma omp parallel for schedule(static) if (blocks > 1)
    for (std::ptrdiff_t b = 0; b < static_cast<std::ptrdiff_t>(blocks); ++b) {
      const std::size_t at = static_cast<std::size_t>(b) * kBlockSize, n = std::min(kBlockSize, size - at);
      out[b].resize(compressBound(n));
      uLongf written = out[b].size();
      failed[b] = compress2(out[b].data(), &written, bytes + at, n, kCompressionLevel) != Z_OK;
      out[b].resize(written);
    }
    for (std::size_t b = 0; b < blocks; ++b) {
      if (failed[b]) throw Error(fmt::format("VTU: zlib could not compress block {} of an array of {} bytes", b, size));
      put<std::uint64_t>(out[b].size());
    }
    for (const auto& block : out) data_.append(reinterpret_cast<const char*>(block.data()), block.size());
  }

  /// zlib's level: on the paper's ball, level 1 writes a frame 1 % larger
  /// than level 6 (its default) in a third of the time (5.3 against 14.7 ms).
  static constexpr int kCompressionLevel = 1;
  VtuFormat format_;
  std::string data_;
};

/// <PointData> or <CellData> with `count` tuples per field.
std::string fields(Arrays& arrays, std::string_view tag, const std::vector<VtuField>& list, Eigen::Index count) {
  std::string out = fmt::format("      <{}>\n", tag);
  for (const auto& field : list) {
    if (field.components < 1 || field.values.size() != static_cast<std::size_t>(field.components * count)) {
      throw Error(fmt::format("VTU {} field '{}': {} values for {} entries of {} components", tag, field.name,
                              field.values.size(), count, field.components));
    }
    if (!field.component_names.empty() && field.component_names.size() != static_cast<std::size_t>(field.components))
      throw Error(fmt::format("VTU {} field '{}': {} component names for {} components", tag, field.name,
                              field.component_names.size(), field.components));
    out += arrays.add_field(field);
  }
  return out + fmt::format("      </{}>\n", tag);
}

std::string points(Arrays& arrays, const Eigen::MatrixXd& p) {
  if (p.rows() < 1 || p.rows() > 3) throw Error(fmt::format("VTU points: {} coordinates per point", p.rows()));
  std::vector<double> xyz(static_cast<std::size_t>(3 * p.cols()), 0.0);
  for (Eigen::Index j = 0; j < p.cols(); ++j) {
    for (Eigen::Index i = 0; i < p.rows(); ++i) xyz[static_cast<std::size_t>(3 * j + i)] = p(i, j);
  }
  return "      <Points>\n" + arrays.add("Float64", "", 3, xyz) + "      </Points>\n";
}

/// The type of a cell of `nodes` nodes when the grid gives no types.
std::uint8_t inferred_type(int nodes) {
  switch (nodes) {
    case 1:
      return kVtkVertex;
    case 2:
      return kVtkLine;
    case 3:
      return kVtkTriangle;
    case 4:
      return kVtkTetra;
    default:
      throw Error(fmt::format("VTU cells: no simplex with {} nodes (quadratic cells need VtuGrid::types)", nodes));
  }
}

/// How many nodes each cell of `grid` has (checked against its column).
std::vector<int> node_counts(const VtuGrid& grid) {
  const auto& c = grid.cells;
  if (!grid.types.empty() && grid.types.size() != static_cast<std::size_t>(c.cols()))
    throw Error(fmt::format("VTU cells: {} types for {} cells", grid.types.size(), c.cols()));
  std::vector<int> counts = grid.nodes_per_cell;
  if (counts.empty() && grid.types.empty())
    counts.assign(static_cast<std::size_t>(c.cols()), static_cast<int>(c.rows()));
  if (counts.empty())
    for (const std::uint8_t type : grid.types) counts.push_back(vtk_cell_nodes(type));
  if (counts.size() != static_cast<std::size_t>(c.cols()))
    throw Error(fmt::format("VTU cells: {} node counts for {} cells", counts.size(), c.cols()));
  for (std::size_t j = 0; j < counts.size(); ++j) {
    if (counts[j] < 1 || counts[j] > c.rows())
      throw Error(fmt::format("VTU cell {}: {} nodes in a column of {}", j, counts[j], c.rows()));
    if (!grid.types.empty() && vtk_cell_nodes(grid.types[j]) != counts[j])
      throw Error(fmt::format("VTU cell {}: type {} with {} nodes", j, grid.types[j], counts[j]));
  }
  return counts;
}

/// Slot i of a VTK cell of `type` holds the cell's (Gmsh-ordered) node
/// slot(type, i): the identity but for a 10-node tetrahedron's edges
/// (1,3) and (2,3), Gmsh's slots 9 and 8.
int gmsh_slot(std::uint8_t type, int i) {
  if (type != kVtkQuadraticTetra || i < 8) return i;
  return i == 8 ? 9 : 8;
}

std::string cells(Arrays& arrays, const VtuGrid& grid) {
  const auto& c = grid.cells;
  const std::vector<int> counts = node_counts(grid);
  std::vector<std::int64_t> connectivity;
  std::vector<std::int64_t> offsets;
  std::vector<std::uint8_t> types;
  for (Eigen::Index j = 0; j < c.cols(); ++j) {
    const int m = counts[static_cast<std::size_t>(j)];
    const std::uint8_t type = grid.types.empty() ? inferred_type(m) : grid.types[static_cast<std::size_t>(j)];
    for (int i = 0; i < m; ++i) {
      const int node = c(gmsh_slot(type, i), j);
      if (node < 0 || node >= grid.points.cols())
        throw Error(fmt::format("VTU cell {}: node {} out of range", j, node));
      connectivity.push_back(node);
    }
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
    types.push_back(type);
  }
  return "      <Cells>\n" + arrays.add("Int64", "connectivity", 1, connectivity) +
         arrays.add("Int64", "offsets", 1, offsets) + arrays.add("UInt8", "types", 1, types) + "      </Cells>\n";
}

}  // namespace

std::uint8_t vtk_cell_type(int dim, int nodes) {
  if (dim >= 0 && dim <= 3 && nodes == dim + 1) return inferred_type(nodes);
  if (dim == 1 && nodes == 3) return kVtkQuadraticEdge;
  if (dim == 2 && nodes == 6) return kVtkQuadraticTriangle;
  if (dim == 3 && nodes == 10) return kVtkQuadraticTetra;
  throw Error(fmt::format("VTU cells: no simplex of dimension {} with {} nodes", dim, nodes));
}

int vtk_cell_nodes(std::uint8_t type) {
  switch (type) {
    case kVtkVertex:
      return 1;
    case kVtkLine:
      return 2;
    case kVtkTriangle:
    case kVtkQuadraticEdge:
      return 3;
    case kVtkTetra:
      return 4;
    case kVtkQuadraticTriangle:
      return 6;
    case kVtkQuadraticTetra:
      return 10;
    default:
      throw Error(fmt::format("VTU cells: unsupported VTK cell type {}", type));
  }
}

std::uintmax_t write_vtu(const std::filesystem::path& file, const VtuGrid& grid, const VtuFormat& format) {
  Arrays arrays(format);
  std::string body = fields(arrays, "PointData", grid.point_data, grid.points.cols());
  body += fields(arrays, "CellData", grid.cell_data, grid.cells.cols());
  body += points(arrays, grid.points);
  body += cells(arrays, grid);
  std::string xml = fmt::format(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"{}\" "
      "header_type=\"UInt64\"{}>\n  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n",
      byte_order, format.compress ? " compressor=\"vtkZLibDataCompressor\"" : "", grid.points.cols(),
      grid.cells.cols());
  xml += body;
  xml += "    </Piece>\n  </UnstructuredGrid>\n  <AppendedData encoding=\"raw\">\n   _";
  xml += arrays.data();
  xml += "\n  </AppendedData>\n</VTKFile>\n";
  write_atomically(file, xml);
  return xml.size();
}

VtuGrid piece(const VtuGrid& grid, Eigen::Index first, Eigen::Index end) {
  VtuGrid out;
  const Eigen::Index cells = end - first, k = grid.cells.rows();
  const auto nodes_of = [&](Eigen::Index c) {
    const auto j = static_cast<std::size_t>(c);
    if (!grid.nodes_per_cell.empty()) return grid.nodes_per_cell[j];
    return grid.types.empty() ? static_cast<int>(k) : vtk_cell_nodes(grid.types[j]);
  };
  std::vector<int> local(static_cast<std::size_t>(grid.points.cols()), -1);
  for (Eigen::Index c = first; c < end; ++c)
    for (int a = 0; a < nodes_of(c); ++a) local[static_cast<std::size_t>(grid.cells(a, c))] = 0;
  std::vector<Eigen::Index> used;
  for (std::size_t n = 0; n < local.size(); ++n)
    if (local[n] == 0) local[n] = static_cast<int>(used.size()), used.push_back(static_cast<Eigen::Index>(n));
  out.points.resize(grid.points.rows(), static_cast<Eigen::Index>(used.size()));
  for (std::size_t n = 0; n < used.size(); ++n) out.points.col(static_cast<Eigen::Index>(n)) = grid.points.col(used[n]);
  out.cells = Eigen::MatrixXi::Zero(k, cells);
  for (Eigen::Index c = first; c < end; ++c) {
    for (int a = 0; a < nodes_of(c); ++a) out.cells(a, c - first) = local[static_cast<std::size_t>(grid.cells(a, c))];
    if (!grid.nodes_per_cell.empty()) out.nodes_per_cell.push_back(nodes_of(c));
    if (!grid.types.empty()) out.types.push_back(grid.types[static_cast<std::size_t>(c)]);
  }
  for (const VtuField& f : grid.point_data) {
    VtuField g{f.name, f.components, {}, f.component_names};
    for (const Eigen::Index n : used)
      g.values.insert(g.values.end(), f.values.begin() + n * f.components, f.values.begin() + (n + 1) * f.components);
    out.point_data.push_back(std::move(g));
  }
  for (const VtuField& f : grid.cell_data) {
    VtuField g{f.name, f.components, {}, f.component_names};
    g.values.assign(f.values.begin() + first * f.components, f.values.begin() + end * f.components);
    out.cell_data.push_back(std::move(g));
  }
  return out;
}

void write_pvtu(const std::filesystem::path& file, const VtuGrid& grid, const VtuFormat& format,
                const std::vector<std::string>& pieces) {
  const char* type = format.single_precision ? "Float32" : "Float64";
  const auto declare = [&](const char* section, const std::vector<VtuField>& fields) {
    std::string xml = fmt::format("    <{}>\n", section);
    for (const VtuField& f : fields)
      xml += fmt::format("      <PDataArray type=\"{}\" Name=\"{}\" NumberOfComponents=\"{}\"/>\n", type,
                         detail::xml_escape(f.name), f.components);
    return xml + fmt::format("    </{}>\n", section);
  };
  std::string xml = fmt::format(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\"{}\" "
      "header_type=\"UInt64\">\n  <PUnstructuredGrid GhostLevel=\"0\">\n",
      byte_order);
  xml += declare("PPointData", grid.point_data);
  xml += declare("PCellData", grid.cell_data);
  xml += "    <PPoints>\n      <PDataArray type=\"Float64\" NumberOfComponents=\"3\"/>\n    </PPoints>\n";
  for (const std::string& p : pieces) xml += fmt::format("    <Piece Source=\"{}\"/>\n", detail::xml_escape(p));
  xml += "  </PUnstructuredGrid>\n</VTKFile>\n";
  write_atomically(file, xml);
}

PvdWriter::PvdWriter(std::filesystem::path file) : file_(std::move(file)) {}

void PvdWriter::resume(double time) {
  std::ifstream in(file_);
  const std::string timestep = "timestep=\"", file = "file=\"";
  for (std::string line; std::getline(in, line);) {
    const auto t = line.find(timestep), f = line.find(file);
    if (t == std::string::npos || f == std::string::npos) continue;
    const double entry_time = std::stod(line.substr(t + timestep.size()));
    const auto begin = f + file.size();
    if (entry_time <= time) entries_.emplace_back(entry_time, line.substr(begin, line.find('"', begin) - begin));
  }
}

void PvdWriter::add(double time, const std::string& relative_file) {
  entries_.emplace_back(time, relative_file);
  std::string xml = fmt::format(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"{}\">\n  <Collection>\n",
      byte_order);
  for (const auto& [t, name] : entries_) {
    xml +=
        fmt::format("    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>\n", t, detail::xml_escape(name));
  }
  xml += "  </Collection>\n</VTKFile>\n";
  try {
    write_atomically(file_, xml);
  } catch (const Error&) {
    entries_.pop_back();  // the file on disk still lists the earlier entries only
    throw;
  }
}

}  // namespace conserve::io
