// SPDX-License-Identifier: BSD-3-Clause
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <cstdlib>
#include <numbers>
#include <ostream>
#include <vrsph/core/error.hpp>
#include <vrsph/core/resources.hpp>
#include <vrsph/io/input_file.hpp>
#include <vrsph/io/output_file.hpp>
#include <vrsph/problem/permeability.hpp>
#include "../cloud/random.hpp"

namespace vrsph {

using detail::concat;

Index PermeabilityField::cell_of(const Vec3& x) const {
  Index c = 0, stride = 1;
  for (int a = 0; a < dim; ++a) {
    const int i = std::clamp(static_cast<int>(std::floor(x[a] * n)), 0, n - 1);
    c += stride * i;
    stride *= n;
  }
  return c;
}

Real PermeabilityField::contrast() const { return k.size() ? k.maxCoeff() / k.minCoeff() : 1; }

bool PermeabilityField::isotropic() const {
  for (int a = 1; a < k.cols(); ++a)
    if (k.col(a) != k.col(0)) return false;
  return true;
}

void validate(const PermeabilityField& f) {
  check<InputError>(f.dim >= 1 && f.dim <= 3, "permeability field: dimension must be 1, 2 or 3, got ", f.dim);
  check<InputError>(f.n >= 1, "permeability field: cells per axis must be >= 1, got ", f.n);
  const double cells_real = std::pow(static_cast<double>(f.n), f.dim);
  check<InputError>(cells_real <= 1e9, "permeability field: ", f.n, "^", f.dim, " cells is more than 1e9");
  const auto cells = static_cast<Index>(cells_real + 0.5);
  check<InputError>(f.k.rows() == cells && f.k.cols() == f.dim, "permeability field: expected ", cells, " x ", f.dim,
                    " values (", f.n, "^", f.dim, " cells, one per direction), got ", f.k.rows(), " x ", f.k.cols());
  for (Index c = 0; c < f.k.rows(); ++c)
    for (int a = 0; a < f.dim; ++a) {
      const Real v = f.k(c, a);
      if (std::isfinite(v) && v > 0) continue;
      const std::int64_t i = c % f.n, j = (c / f.n) % f.n, l = c / (std::int64_t{f.n} * f.n);
      throw InputError(concat("permeability field: k_", "xyz"[a], " of cell (I, J, K) = (", i + 1, ", ", j + 1, ", ",
                              l + 1, ") is ", v, "; permeabilities must be finite and > 0"));
    }
}

namespace {

PermeabilityField empty_field(int dim, int n) {
  check<ConfigError>(dim >= 1 && dim <= 3, "permeability field: dimension must be 1, 2 or 3, got ", dim);
  check<ConfigError>(n >= 1 && n <= 4096, "permeability field: cells per axis must be in 1..4096, got ", n);
  const double cells = std::pow(static_cast<double>(n), dim);
  check<ConfigError>(cells <= 1e8, "permeability field: ", n, "^", dim, " = ", cells, " cells is more than 1e8");
  // The values, and the padded noise of the log-normal generator (up to twice as many).
  check_memory_estimate(3 * cells * dim * sizeof(Real), "permeability field", "use fewer cells per axis");
  PermeabilityField f;
  f.dim = dim;
  f.n = n;
  f.k.resize(static_cast<Index>(std::pow(static_cast<double>(n), dim) + 0.5), dim);
  return f;
}

// Standard normal numbers from the counter-based generator (Box–Muller): the same field on
// every platform and thread count.
Real normal(std::uint64_t seed, std::uint64_t counter) {
  const Real u1 = 1 - detail::uniform01(seed, 11, 2 * counter), u2 = detail::uniform01(seed, 11, 2 * counter + 1);
  return std::sqrt(-2 * std::log(u1)) * std::cos(2 * std::numbers::pi * u2);
}

// Unit-variance Gaussian field on the n^dim cell centres with covariance exp(-r²/ℓ²): white
// noise on a grid padded by 3ℓ, convolved axis by axis with g(s) = exp(-2 s²/ℓ²) (g * g has
// the wanted covariance) and divided by the discrete norm of the full kernel.
std::vector<Real> gaussian_field(int dim, int n, Real ell, std::uint64_t seed) {
  const Real dx = 1.0 / n;
  const int pad = ell > 0 ? static_cast<int>(std::ceil(3 * ell / dx)) : 0;
  std::vector<Real> g(static_cast<std::size_t>(2 * pad + 1));
  Real norm2 = 0;
  for (int s = -pad; s <= pad; ++s) {
    g[static_cast<std::size_t>(s + pad)] = ell > 0 ? std::exp(-2 * (s * dx) * (s * dx) / (ell * ell)) : 1;
    norm2 += g[static_cast<std::size_t>(s + pad)] * g[static_cast<std::size_t>(s + pad)];
  }
  std::array<Index, 3> ext{1, 1, 1};
  for (int a = 0; a < dim; ++a) ext[static_cast<std::size_t>(a)] = n + 2 * pad;
  std::vector<Real> field(static_cast<std::size_t>(ext[0] * ext[1] * ext[2]));
  for (std::size_t c = 0; c < field.size(); ++c) field[c] = normal(seed, c);
  // Each pass shrinks one axis from n + 2 pad to n (the valid part of the convolution).
  for (int a = 0; a < dim; ++a) {
    std::array<Index, 3> out_ext = ext;
    out_ext[static_cast<std::size_t>(a)] = n;
    std::vector<Real> out(static_cast<std::size_t>(out_ext[0] * out_ext[1] * out_ext[2]), 0.0);
    const Index stride = a == 0 ? 1 : a == 1 ? ext[0] : ext[0] * ext[1];
#pragma omp parallel for collapse(2) schedule(static) if (out.size() > 65536)
    for (Index l = 0; l < out_ext[2]; ++l)
      for (Index j = 0; j < out_ext[1]; ++j)
        for (Index i = 0; i < out_ext[0]; ++i) {
          const Index base = i + ext[0] * (j + ext[1] * l);  // same (i, j, l) in the input: the window starts there
          Real sum = 0;
          for (int s = 0; s <= 2 * pad; ++s) sum += g[static_cast<std::size_t>(s)] * field[static_cast<std::size_t>(base + s * stride)];
          out[static_cast<std::size_t>(i + out_ext[0] * (j + out_ext[1] * l))] = sum;
        }
    field.swap(out);
    ext = out_ext;
  }
  const Real scale = 1 / std::sqrt(std::pow(norm2, dim));
  for (Real& v : field) v *= scale;
  return field;
}

void fill_directions(PermeabilityField& f, const std::vector<Real>& k, Real kz_ratio) {
  for (Index c = 0; c < f.cells(); ++c)
    for (int a = 0; a < f.dim; ++a) f.k(c, a) = k[static_cast<std::size_t>(c)] * (a == 2 ? kz_ratio : 1);
}

void check_kz_ratio(Real r) {
  check<ConfigError>(std::isfinite(r) && r > 0, "permeability field: kz ratio must be finite and > 0, got ", r);
}

}  // namespace

PermeabilityField lognormal_permeability(int dim, int n, const LognormalFieldOptions& o) {
  check<ConfigError>(std::isfinite(o.k_mean) && o.k_mean > 0, "log-normal field: mean permeability must be > 0, got ",
                     o.k_mean);
  check<ConfigError>(std::isfinite(o.sigma_ln) && o.sigma_ln >= 0 && o.sigma_ln <= 20,
                     "log-normal field: sigma of ln k must be in [0, 20], got ", o.sigma_ln);
  check<ConfigError>(std::isfinite(o.correlation_length) && o.correlation_length >= 0 && o.correlation_length <= 10,
                     "log-normal field: correlation length must be in [0, 10] (units of the domain), got ",
                     o.correlation_length);
  check_kz_ratio(o.kz_ratio);
  PermeabilityField f = empty_field(dim, n);
  std::vector<Real> z = gaussian_field(dim, n, o.correlation_length, o.seed);
  for (Real& v : z) v = o.k_mean * std::exp(o.sigma_ln * v);
  fill_directions(f, z, o.kz_ratio);
  validate(f);  // exp overflow at extreme sigma would show here, named
  return f;
}

PermeabilityField channel_permeability(int dim, int n, const ChannelFieldOptions& o) {
  check<ConfigError>(dim >= 2, "channelised field: needs 2D or 3D, got ", dim, "D");
  check<ConfigError>(std::isfinite(o.k_background) && o.k_background > 0,
                     "channelised field: background permeability must be > 0, got ", o.k_background);
  check<ConfigError>(std::isfinite(o.contrast) && o.contrast >= 1 && o.k_background * o.contrast < 1e300,
                     "channelised field: contrast must be >= 1 and keep k finite, got ", o.contrast);
  check<ConfigError>(o.channels >= 0 && o.channels <= 1000, "channelised field: channels must be in 0..1000, got ",
                     o.channels);
  check_kz_ratio(o.kz_ratio);
  PermeabilityField f = empty_field(dim, n);
  const int count = o.channels > 0 ? o.channels : dim == 2 ? 4 : 8;
  struct Channel {
    Real x0, angle, amplitude, wavelength, phase, width, z0, thickness;
  };
  std::vector<Channel> ch;
  for (int c = 0; c < count; ++c) {
    const auto u = [&](int k) { return detail::uniform01(o.seed, 17, static_cast<std::uint64_t>(8 * c + k)); };
    ch.push_back({0.1 + 0.8 * u(0), (u(1) - 0.5) * std::numbers::pi / 2, 0.03 + 0.09 * u(2), 0.3 + 0.5 * u(3),
                  2 * std::numbers::pi * u(4), 0.04 + 0.06 * u(5), 0.1 + 0.8 * u(6), 0.08 + 0.12 * u(7)});
  }
  std::vector<Real> k(static_cast<std::size_t>(f.cells()), o.k_background);
  for (Index c = 0; c < f.cells(); ++c) {
    const Real x = (static_cast<Real>(c % n) + 0.5) / n, y = (static_cast<Real>((c / n) % n) + 0.5) / n,
               z = (static_cast<Real>(c / (static_cast<Index>(n) * n)) + 0.5) / n;
    for (const Channel& h : ch) {
      // Along-axis s and across-axis t from the channel's anchor (x0, 0.5).
      const Real dxp = x - h.x0, dyp = y - 0.5;
      const Real s = dxp * std::sin(h.angle) + dyp * std::cos(h.angle), t = dxp * std::cos(h.angle) - dyp * std::sin(h.angle);
      const bool across = std::abs(t - h.amplitude * std::sin(2 * std::numbers::pi * s / h.wavelength + h.phase)) <= h.width / 2;
      if (across && (dim == 2 || std::abs(z - h.z0) <= h.thickness / 2)) {
        k[static_cast<std::size_t>(c)] = o.k_background * o.contrast;
        break;
      }
    }
  }
  fill_directions(f, k, o.kz_ratio);
  return f;
}

namespace {

std::vector<Real> parse_numbers(std::string text, const std::string& path) {
  for (char& ch : text)
    if (ch == 'D' || ch == 'd') ch = 'E';  // Fortran double-precision exponents
  std::vector<Real> values;
  values.reserve(text.size() / 8);
  const char* p = text.c_str();
  const char* end = p + text.size();
  long long line = 1;
  while (true) {
    while (p < end && std::isspace(static_cast<unsigned char>(*p))) {
      if (*p == '\n') ++line;
      ++p;
    }
    if (p >= end) break;
    char* stop = nullptr;
    const Real v = std::strtod(p, &stop);
    const bool separated = stop < end ? std::isspace(static_cast<unsigned char>(*stop)) != 0 : true;
    if (stop == p || !separated) {
      const char* q = p;
      while (q < end && !std::isspace(static_cast<unsigned char>(*q)) && q - p < 40) ++q;
      throw InputError(concat("permeability file ", path, ", line ", line, ": '", std::string(p, q),
                              "' is not a number (value ", values.size() + 1, ")"));
    }
    values.push_back(v);
    p = stop;
  }
  return values;
}

}  // namespace

PermeabilityField read_permeability(const std::string& path, const PermeabilityFileLayout& L) {
  check<ConfigError>(L.dim >= 1 && L.dim <= 3, "permeability file: dimension must be 1, 2 or 3, got ", L.dim);
  // 64-bit counts: a grid of up to 100000^3 cells overflows 32 bits long before it fails to fit.
  std::int64_t file_cells = 1;
  for (int a = 0; a < 3; ++a) {
    check<ConfigError>(L.grid[static_cast<std::size_t>(a)] >= 1 && L.grid[static_cast<std::size_t>(a)] <= 100000,
                       "permeability file: grid size ", "IJK"[a], " = ", L.grid[static_cast<std::size_t>(a)],
                       " must be in 1..100000");
    file_cells *= L.grid[static_cast<std::size_t>(a)];
  }
  // Every value takes at least two characters (a digit and a separator): a file shorter than
  // that cannot hold a large grid, and is refused before it is read or anything is allocated
  // (a small one is read, and its count of values named).
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  check<InputError>(ec || file_cells < (1 << 20) || bytes >= 2 * static_cast<std::uintmax_t>(file_cells) - 1,
                    "permeability file ", path, " has ",
                    bytes, " bytes: too short for the ", file_cells, " values of the grid ", L.grid[0], " x ", L.grid[1],
                    " x ", L.grid[2], " (check --perm-grid)");
  int n = 0;
  for (int a = 0; a < 3; ++a) {
    const auto [lo, hi] = L.subset[static_cast<std::size_t>(a)];
    check<ConfigError>(lo >= 1 && lo <= hi && hi <= L.grid[static_cast<std::size_t>(a)], "permeability subset ",
                       "IJK"[a], " = ", lo, ":", hi, " is not a range inside 1:", L.grid[static_cast<std::size_t>(a)]);
    const int len = hi - lo + 1;
    if (a < L.dim) {
      check<ConfigError>(n == 0 || len == n, "permeability subset must be square (cubic): ", "IJK"[a], " has ", len,
                         " cells, ", "IJK"[0], " has ", n);
      n = len;
    } else {
      check<ConfigError>(len == 1, "permeability subset: a ", L.dim, "D field takes one index in ", "IJK"[a], ", got ",
                         lo, ":", hi);
    }
  }
  const std::vector<Real> v = parse_numbers(read_file(path, "permeability file"), path);
  const auto count = static_cast<std::int64_t>(v.size());
  const std::int64_t blocks = count / file_cells;
  check<InputError>(!v.empty() && count % file_cells == 0 && blocks >= 1 && blocks <= 3,
                    "permeability file ", path, " has ", v.size(), " values; the grid ", L.grid[0], " x ", L.grid[1],
                    " x ", L.grid[2], " needs ", file_cells, " (isotropic), ", 2 * file_cells, " (k_x, k_y) or ",
                    3 * file_cells, " (k_x, k_y, k_z)");
  check<InputError>(blocks == 1 || blocks >= L.dim, "permeability file ", path, " has ", blocks,
                    " direction blocks; a ", L.dim, "D field needs ", L.dim, " (or 1: isotropic)");
  PermeabilityField f = empty_field(L.dim, n);
  for (Index c = 0; c < f.cells(); ++c) {
    const std::int64_t i = c % n + L.subset[0][0] - 1, j = (L.dim > 1 ? (c / n) % n : 0) + L.subset[1][0] - 1,
                       l = (L.dim > 2 ? c / (static_cast<std::int64_t>(n) * n) : 0) + L.subset[2][0] - 1;
    const std::int64_t src = i + std::int64_t{L.grid[0]} * (j + std::int64_t{L.grid[1]} * l);
    for (int a = 0; a < L.dim; ++a) f.k(c, a) = v[static_cast<std::size_t>((blocks == 1 ? 0 : a) * file_cells + src)];
  }
  try {
    validate(f);
  } catch (const InputError& e) {
    throw InputError(concat("permeability file ", path, ": ", e.what()));
  }
  return f;
}

void write_permeability(const std::string& path, const PermeabilityField& f) {
  validate(f);
  write_file(path, "permeability file", [&](std::ostream& out) {
    out.precision(17);
    int on_line = 0;
    for (int a = 0; a < f.dim; ++a)
      for (Index c = 0; c < f.cells(); ++c) {
        out << f.k(c, a) << (++on_line % 6 == 0 ? '\n' : ' ');
      }
    out << '\n';
  });
}

}  // namespace vrsph
