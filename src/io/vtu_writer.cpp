/// VTK XML UnstructuredGrid (binary, base64 inline, UInt64 headers) and PVD.
#include "io/vtu_writer.hpp"

#include <fstream>

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>

#include "core/error.hpp"
#include "io/atomic_file.hpp"

namespace conserve::io {
namespace {

constexpr std::string_view byte_order = std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian";

std::string base64(const std::vector<unsigned char>& bytes) {
  static constexpr char alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t word = 0;
    for (std::size_t k = 0; k < 3; ++k) word = (word << 8) | (k < n ? bytes[i + k] : 0u);
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? alphabet[(word >> (18 - 6 * k)) & 63u] : '=';
  }
  return out;
}

/// base64(UInt64 byte count + raw values), the inline binary encoding.
template <typename T>
std::string encode(const std::vector<T>& values) {
  const std::uint64_t size = values.size() * sizeof(T);
  std::vector<unsigned char> bytes(sizeof size + size);
  std::memcpy(bytes.data(), &size, sizeof size);
  if (size > 0) std::memcpy(bytes.data() + sizeof size, values.data(), size);
  return base64(bytes);
}

template <typename T>
std::string data_array(std::string_view type, std::string_view name, int components, const std::vector<T>& values) {
  const auto name_attribute = name.empty() ? std::string() : fmt::format(" Name=\"{}\"", detail::xml_escape(name));
  return fmt::format("        <DataArray type=\"{}\"{} NumberOfComponents=\"{}\" format=\"binary\">{}</DataArray>\n",
                     type, name_attribute, components, encode(values));
}

/// <PointData> or <CellData> with `count` tuples per field.
std::string fields(std::string_view tag, const std::vector<VtuField>& list, Eigen::Index count) {
  std::string out = fmt::format("      <{}>\n", tag);
  for (const auto& field : list) {
    if (field.components < 1 || field.values.size() != static_cast<std::size_t>(field.components * count)) {
      throw Error(fmt::format("VTU {} field '{}': {} values for {} entries of {} components", tag, field.name,
                              field.values.size(), count, field.components));
    }
    out += data_array("Float64", field.name, field.components, field.values);
  }
  return out + fmt::format("      </{}>\n", tag);
}

std::string points(const Eigen::MatrixXd& p) {
  if (p.rows() < 1 || p.rows() > 3) throw Error(fmt::format("VTU points: {} coordinates per point", p.rows()));
  std::vector<double> xyz(static_cast<std::size_t>(3 * p.cols()), 0.0);
  for (Eigen::Index j = 0; j < p.cols(); ++j) {
    for (Eigen::Index i = 0; i < p.rows(); ++i) xyz[static_cast<std::size_t>(3 * j + i)] = p(i, j);
  }
  return "      <Points>\n" + data_array("Float64", "", 3, xyz) + "      </Points>\n";
}

std::uint8_t cell_type(int nodes_per_cell) {
  switch (nodes_per_cell) {
    case 1:
      return 1;  // VTK_VERTEX
    case 2:
      return 3;  // VTK_LINE
    case 3:
      return 5;  // VTK_TRIANGLE
    case 4:
      return 10;  // VTK_TETRA
    default:
      throw Error(fmt::format("VTU cells: no simplex with {} nodes", nodes_per_cell));
  }
}

/// How many nodes each cell of `grid` has (checked against its column).
std::vector<int> node_counts(const VtuGrid& grid) {
  const auto& c = grid.cells;
  if (grid.nodes_per_cell.empty())
    return std::vector<int>(static_cast<std::size_t>(c.cols()), static_cast<int>(c.rows()));
  if (grid.nodes_per_cell.size() != static_cast<std::size_t>(c.cols()))
    throw Error(fmt::format("VTU cells: {} node counts for {} cells", grid.nodes_per_cell.size(), c.cols()));
  for (std::size_t j = 0; j < grid.nodes_per_cell.size(); ++j) {
    if (grid.nodes_per_cell[j] < 1 || grid.nodes_per_cell[j] > c.rows())
      throw Error(fmt::format("VTU cell {}: {} nodes in a column of {}", j, grid.nodes_per_cell[j], c.rows()));
  }
  return grid.nodes_per_cell;
}

std::string cells(const VtuGrid& grid) {
  const auto& c = grid.cells;
  const std::vector<int> counts = node_counts(grid);
  std::vector<std::int64_t> connectivity;
  std::vector<std::int64_t> offsets;
  std::vector<std::uint8_t> types;
  for (Eigen::Index j = 0; j < c.cols(); ++j) {
    const int m = counts[static_cast<std::size_t>(j)];
    for (Eigen::Index i = 0; i < m; ++i) {
      if (c(i, j) < 0 || c(i, j) >= grid.points.cols()) {
        throw Error(fmt::format("VTU cell {}: node {} out of range", j, c(i, j)));
      }
      connectivity.push_back(c(i, j));
    }
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
    types.push_back(cell_type(m));
  }
  return "      <Cells>\n" + data_array("Int64", "connectivity", 1, connectivity) +
         data_array("Int64", "offsets", 1, offsets) + data_array("UInt8", "types", 1, types) + "      </Cells>\n";
}

}  // namespace

void write_vtu(const std::filesystem::path& file, const VtuGrid& grid) {
  std::string xml = fmt::format(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"{}\" "
      "header_type=\"UInt64\">\n  <UnstructuredGrid>\n    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n",
      byte_order, grid.points.cols(), grid.cells.cols());
  xml += fields("PointData", grid.point_data, grid.points.cols());
  xml += fields("CellData", grid.cell_data, grid.cells.cols());
  xml += points(grid.points);
  xml += cells(grid);
  xml += "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
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
