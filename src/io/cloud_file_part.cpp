// SPDX-License-Identifier: BSD-3-Clause
// A cloud file read by several ranks together: CSV by byte ranges (each rank parses only
// its own rows), other formats on rank 0 and handed out in slices. See cloud_file.hpp.
#include <array>
#include <filesystem>
#include <limits>
#include <vrsph/core/error.hpp>
#include <vrsph/core/parse.hpp>
#include <vrsph/io/cloud_file.hpp>
#include <vrsph/io/input_file.hpp>
#include "csv_rows.hpp"

namespace vrsph {

namespace {
using detail::concat;

bool is_csv(const std::string& path) {
  const std::string ext = to_lower(std::filesystem::path(path).extension().string());
  return ext != ".vtu" && ext != ".vtp" && ext != ".msh";
}

// The complete lines that start in [begin, end) of the file (a line starts at `begin` when
// the byte before it ends a line). Rank r's begin is rank r-1's end, so every line is
// read by exactly one rank.
std::vector<std::string> lines_starting_in(std::ifstream& in, std::size_t begin, std::size_t end, const std::string& path) {
  std::vector<std::string> lines;
  if (begin >= end) return lines;
  in.clear();
  in.seekg(static_cast<std::streamoff>(begin - 1));  // begin >= 1: the header comes first
  std::string line;
  std::size_t at = begin;
  if (in.get() != '\n') {  // inside a line that an earlier rank reads: skip to its end
    std::getline(in, line);
    at += line.size() + 1;
  }
  while (at < end && std::getline(in, line)) {
    at += line.size() + 1;
    lines.push_back(std::move(line));
  }
  check<IoError>(!in.bad(), "cannot read point cloud file '", path, "'");
  return lines;
}

CloudFilePart read_csv_in_ranges(const std::string& path, int dim, const Communicator& comm) {
  detail::CsvHeader h;
  std::vector<std::string> lines;
  collective(comm, [&] {
    std::ifstream in = open_input(path, "point cloud file");
    h = detail::read_csv_header(in, path, true);
    const std::streamoff header_end = in.tellg();
    const std::size_t size = std::filesystem::file_size(path);
    const std::size_t body_begin = header_end < 0 ? size : static_cast<std::size_t>(header_end);
    const auto bound = [&](int r) {
      return body_begin + static_cast<std::size_t>(static_cast<long double>(size - body_begin) * r / comm.size());
    };
    lines = lines_starting_in(in, bound(comm.rank()), bound(comm.rank() + 1), path);
  });
  // Line numbers: the header's lines, then the lines of the ranks before this one.
  const auto first_line = static_cast<std::size_t>(offset_over_ranks(comm, static_cast<long long>(lines.size()))) + h.lines;
  detail::CsvRows rows;
  rows.file.source = path;
  collective(comm, [&] {
    for (std::size_t k = 0; k < lines.size(); ++k) detail::parse_csv_row(lines[k], first_line + k + 1, h, path, rows);
  });
  lines = {};
  CloudFilePart part;
  const long long mine = rows.file.cloud.size();
  part.total = static_cast<Index>(sum_over_ranks(comm, mine));
  part.first = static_cast<Index>(offset_over_ranks(comm, mine));
  Vec3 any_nonzero;
  for (int k = 0; k < 3; ++k) any_nonzero[k] = max_over_ranks(comm, rows.any_nonzero[k]);
  collective(comm, [&] {
    check<InputError>(part.total > 0, path, ": no particles after the header");
    detail::finish_csv_rows(rows, h, detail::settle_csv_dimension(h, any_nonzero, dim, path));
  });
  part.file = std::move(rows.file);
  return part;
}

// Rank 0 reads the whole file; each rank gets the slice [N r / P, N (r + 1) / P) of every
// column (positions, tags, normals, fields) and the file's layout (dimension, field names).
CloudFilePart read_on_root_and_scatter(const std::string& path, int dim, const Communicator& comm) {
  CloudFile whole;
  collective(comm, [&] {
    if (comm.is_root()) whole = read_cloud_file(path, dim);
  });
  std::vector<std::string> names;
  for (const auto& f : whole.fields) names.push_back(f.name);
  names = gather_strings(comm, names);  // rank 0's only
  CloudFilePart part;
  part.total = static_cast<Index>(sum_over_ranks(comm, static_cast<long long>(whole.cloud.size())));
  const auto t = static_cast<long long>(part.total);
  part.first = static_cast<Index>(t * comm.rank() / comm.size());
  const long long count = t * (comm.rank() + 1) / comm.size() - part.first;
  const bool normals = any_rank(comm, whole.cloud.has_normals());
  PointCloud& c = part.file.cloud;
  c.dim = static_cast<int>(max_over_ranks(comm, static_cast<double>(whole.cloud.dim)));
  c.spacing = max_over_ranks(comm, whole.cloud.spacing);
  part.file.source = path;
  const auto column = [&](auto value_of) {  // one column of rank 0's cloud, scattered
    std::vector<double> all;
    if (comm.is_root())
      for (Index i = 0; i < whole.cloud.size(); ++i) all.push_back(value_of(static_cast<std::size_t>(i)));
    return scatter_from_root(comm, all, count);
  };
  std::array<std::vector<double>, 3> x, n;
  for (int k = 0; k < 3; ++k) {
    x[static_cast<std::size_t>(k)] = column([&](std::size_t i) { return whole.cloud.positions[i][k]; });
    if (normals) n[static_cast<std::size_t>(k)] = column([&](std::size_t i) { return whole.cloud.normals[i][k]; });
  }
  const std::vector<double> tags = column([&](std::size_t i) { return static_cast<double>(whole.cloud.tags[i]); });
  for (long long i = 0; i < count; ++i) {
    const auto si = static_cast<std::size_t>(i);
    c.positions.emplace_back(x[0][si], x[1][si], x[2][si]);
    c.tags.push_back(static_cast<Tag>(static_cast<int>(tags[si])));
    if (normals) c.normals.emplace_back(n[0][si], n[1][si], n[2][si]);
  }
  // A periodic box the file records (VTU field data): rank 0's, on every rank.
  if (any_rank(comm, whole.cloud.domain.any_periodic())) {
    const auto from_root = [&](double v) {
      return max_over_ranks(comm, comm.is_root() ? v : -std::numeric_limits<double>::infinity());
    };
    Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();
    std::string axes;
    for (int k = 0; k < c.dim; ++k) {
      lo[k] = from_root(whole.cloud.domain.lo[k]);
      hi[k] = from_root(whole.cloud.domain.hi[k]);
      if (from_root(whole.cloud.domain.periodic[static_cast<std::size_t>(k)] ? 1 : 0) > 0)
        axes += std::string(axes.empty() ? "" : ",") + "xyz"[k];
    }
    c.domain = Domain::periodic_box(c.dim, lo, hi, axes);
  }
  for (std::size_t f = 0; f < names.size(); ++f) {
    const std::vector<double> v = column([&](std::size_t i) { return whole.fields[f].values[static_cast<Index>(i)]; });
    part.file.fields.push_back({names[f], Eigen::Map<const Field>(v.data(), static_cast<Eigen::Index>(v.size()))});
  }
  return part;
}
}  // namespace

CloudFilePart read_cloud_file_part(const std::string& path, int dim, const Communicator& comm) {
  check<InputError>(dim >= 0 && dim <= 3, "requested dimension must be 1, 2 or 3, got ", dim);
  if (!comm.distributed()) {
    CloudFilePart part;
    part.file = read_cloud_file(path, dim);
    part.total = part.file.cloud.size();
    return part;
  }
  // Byte ranges need a regular file (a pipe has no size and no seek).
  std::error_code ec;
  if (is_csv(path) && std::filesystem::is_regular_file(path, ec)) return read_csv_in_ranges(path, dim, comm);
  return read_on_root_and_scatter(path, dim, comm);
}

}  // namespace vrsph
