// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The CSV cloud reader in pieces (csv.cpp), so that a file can also be read by several
// ranks, each its own byte range of the rows (cloud_file_part.cpp): the header, one row,
// and the dimension that all rows together settle.
#include <cstddef>
#include <iosfwd>
#include <map>
#include <optional>
#include <string>
#include <vector>
#include <vrsph/io/cloud_file.hpp>

namespace vrsph::detail {

struct CsvHeader {
  std::size_t lines = 0;   ///< lines up to and including the header
  std::size_t fields = 0;  ///< fields per row
  std::map<std::string, std::size_t> col;  ///< lower-case column name -> position
  std::vector<std::size_t> extra_col;      ///< positions of the extra (field) columns
  std::vector<std::string> extra_names;
  int coord_cols = 1;
  bool normals = false;
  /// A periodic box recorded before the header ("# vrsph domain: lo=.. hi=.. periodic=.."),
  /// as write_csv records a periodic cloud's; the cloud takes it once its dimension is settled.
  std::optional<Domain> domain;
  std::size_t domain_line = 0;
};

/// Rows read so far: the cloud (dim not yet settled), the extra columns, and which
/// coordinates are non-zero somewhere.
struct CsvRows {
  CloudFile file;
  std::vector<std::vector<Real>> extra;
  Vec3 any_nonzero = Vec3::Zero();
};

/// Reads through the header line (the first non-blank line that is not a '#' comment). Throws InputError.
CsvHeader read_csv_header(std::istream& in, const std::string& name, bool tag_required);
/// Parses line number `lineno` (blank lines are skipped). Throws InputError naming the line.
void parse_csv_row(const std::string& line, std::size_t lineno, const CsvHeader& h, const std::string& name,
                   CsvRows& out);
/// The cloud's dimension from the non-zero coordinates of *all* rows and the requested one
/// (none requested: a recorded box's).
int settle_csv_dimension(const CsvHeader& h, const Vec3& any_nonzero, int dim, const std::string& name);
/// Sets the dimension, trims the normals to it, validates, gives the cloud the recorded box (its
/// particles in it), and moves the extra columns into fields.
void finish_csv_rows(CsvRows& rows, const CsvHeader& h, int dim);

}  // namespace vrsph::detail
