// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// Point clouds as CSV. Header line required; columns (any order, case-insensitive):
//   x[,y[,z]], tag[, nx[,ny[,nz]]], and any further numeric columns (per-particle fields,
//   e.g. a coefficient or a right-hand side: read_csv_with_fields keeps them).
// tag is interior|dirichlet|neumann|ghost or 0..3. The dimension is the number of
// coordinate columns up to the last one that is not identically zero, unless a
// dimension is requested (then extra coordinates must be zero: else a mismatch).
// Lines starting with '#' before the header are comments; one of them may record a periodic
// box, "# vrsph domain: lo=0,0 hi=1,1 periodic=x,y", which write_csv writes for a periodic
// cloud and the reader gives back (it also settles the dimension when none is requested).
#include <iosfwd>
#include <string>
#include <vrsph/cloud/point_cloud.hpp>
#include <vrsph/io/cloud_file.hpp>

namespace vrsph {

/// Throws InputError naming the file, line and problem (missing file, empty file,
/// missing header/columns, wrong field count, non-numeric or non-finite values,
/// unknown tag, dimension mismatch).
PointCloud read_csv(const std::string& path, int dim = 0);
PointCloud read_csv(std::istream& in, const std::string& name, int dim = 0);
/// The cloud and its extra columns as fields (names lower-cased, in file order); every
/// value of an extra column must be a finite number.
CloudFile read_csv_with_fields(const std::string& path, int dim = 0);
CloudFile read_csv_with_fields(std::istream& in, const std::string& name, int dim = 0);
/// As read_csv_with_fields; with tag_required = false a file without a tag column is
/// accepted (every point Interior), e.g. evaluation points `x,y[,z]`.
CloudFile read_csv_columns(std::istream& in, const std::string& name, int dim, bool tag_required);
/// Evaluation points from a CSV file with columns x[,y[,z]] (a tag column is allowed and ignored).
std::vector<Vec3> read_points_csv(const std::string& path, int dim);

/// Writes x,y,z,tag[,nx,ny,nz] and one column per field (a cloud file's data columns, so a
/// conversion keeps them) with 17 significant digits (lossless round trip).
void write_csv(const std::string& path, const PointCloud& cloud, const std::vector<NamedField>& fields = {});
void write_csv(std::ostream& out, const PointCloud& cloud);

}  // namespace vrsph
