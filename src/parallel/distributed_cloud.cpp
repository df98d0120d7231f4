// SPDX-License-Identifier: BSD-3-Clause
// Morton partition, halos and their PetscSF exchanges (see distributed_cloud.hpp); built with
// VRSPH_WITH_MPI only (distributed_spacing.cpp holds what a serial build needs too).
//
// Three star forests:
//  - migration: leaves = the input chunk's particles, roots = the owner's arrival slots.
//    Reduce (REPLACE) moves chunk data to the owners; Bcast moves owners' data back.
//  - push (temporary): leaves = (owned particle, receiving rank) pairs, roots = halo slots
//    on the receiver; it carries the halo particles and the owners' local indices once.
//  - halo: leaves = halo entries of the local arrays, roots = the owners' local arrays.
//    Bcast (REPLACE) is the ghost update.
// The counts behind the first two come from MPI_Alltoall (one integer per rank pair).
//
// A box periodic along some axes: a halo entry may be an image, the owner's particle moved by
// whole periods (periodic.hpp's shift codes). It is pushed, already moved, to every rank (the
// owner itself too) whose pieces lie within the halo width of the image; its global number is
// the original's, and the ghost update copies the original's value to it, as the serial
// periodic partition does with its images. The local arrays then hold the images explicitly,
// and their searches run without the minimum image.
#include <petscsf.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <vrsph/core/error.hpp>
#include <vrsph/neighbours/periodic.hpp>
#include <vrsph/parallel/distributed_cloud.hpp>
#include "petsc_runtime.hpp"

namespace vrsph {

namespace detail {
struct CloudExchange {
  MPI_Comm comm = MPI_COMM_NULL;
  PetscSF migration = nullptr;
  PetscSF halo = nullptr;
  Index chunk_size = 0;
  std::vector<Index> arrival_to_local;  ///< migration root slot -> local index
  CloudExchange() = default;
  CloudExchange(const CloudExchange&) = delete;
  CloudExchange& operator=(const CloudExchange&) = delete;
  ~CloudExchange() {
    PetscBool finalised = PETSC_TRUE;
    if (PetscFinalized(&finalised) == 0 && finalised) return;  // PETSc already gone at exit: nothing to free
    if (halo) PetscSFDestroy(&halo);
    if (migration) PetscSFDestroy(&migration);
  }
};
}  // namespace detail

namespace {
using detail::CloudExchange;

// A serial Communicator is this process alone, even inside an mpirun job.
MPI_Comm mpi_or_self(const Communicator& c) { return c.distributed() ? MPI_Comm_f2c(c.fortran_handle()) : MPI_COMM_SELF; }

void sf_call(PetscErrorCode code, const char* what) {
  if (code != 0) throw NumericalError(detail::concat("PETSc star forest (", what, ") failed with error ", code));
}

// A graph with contiguous leaves 0..remote.size()-1 (ilocal null) or at `ilocal`.
PetscSF make_sf(MPI_Comm comm, Index nroots, std::vector<PetscSFNode>& remote, std::vector<PetscInt>* ilocal) {
  PetscSF sf = nullptr;
  sf_call(PetscSFCreate(comm, &sf), "create");
  sf_call(PetscSFSetGraph(sf, nroots, static_cast<PetscInt>(remote.size()), ilocal ? ilocal->data() : nullptr,
                       PETSC_COPY_VALUES, remote.data(), PETSC_COPY_VALUES),
       "graph");
  sf_call(PetscSFSetUp(sf), "set-up");
  return sf;
}

template <class T>
MPI_Datatype mpi_type() {
  if constexpr (std::is_same_v<T, double>) return MPI_DOUBLE;
  else if constexpr (std::is_same_v<T, int>) return MPI_INT;
  else return MPI_BYTE;  // char, std::uint8_t (Tag)
}

// `width` consecutive values of T as one MPI unit, freed with the scope.
template <class T>
struct Unit {
  MPI_Datatype type = mpi_type<T>();
  bool owned = false;
  explicit Unit(int width) {
    if (width == 1) return;
    MPI_Type_contiguous(width, mpi_type<T>(), &type);
    MPI_Type_commit(&type);
    owned = true;
  }
  ~Unit() {
    if (owned) MPI_Type_free(&type);
  }
  Unit(const Unit&) = delete;
  Unit& operator=(const Unit&) = delete;
};

// leaf -> root (each root has one leaf)
template <class T>
void reduce(PetscSF sf, const T* leaf, T* root, int width = 1) {
  const Unit<T> unit(width);
  sf_call(PetscSFReduceBegin(sf, unit.type, leaf, root, MPI_REPLACE), "reduce");
  sf_call(PetscSFReduceEnd(sf, unit.type, leaf, root, MPI_REPLACE), "reduce");
}
// root -> leaves
template <class T>
void bcast(PetscSF sf, const T* root, T* leaf, int width = 1) {
  const Unit<T> unit(width);
  sf_call(PetscSFBcastBegin(sf, unit.type, root, leaf, MPI_REPLACE), "broadcast");
  sf_call(PetscSFBcastEnd(sf, unit.type, root, leaf, MPI_REPLACE), "broadcast");
}

// Leaves sent to ranks `dest` (one per leaf, any order): the root slot of each leaf on its
// receiving rank, ranks' slots filled in sender-rank order. Returns the receiver's root count
// and, per sending rank, where its slots begin (recv_begin, size P + 1).
Index slots_for(MPI_Comm comm, int ranks, const std::vector<int>& dest, std::vector<PetscSFNode>& remote,
                std::vector<int>& recv_begin) {
  std::vector<int> send(static_cast<std::size_t>(ranks), 0), recv(static_cast<std::size_t>(ranks), 0);
  for (int d : dest) ++send[static_cast<std::size_t>(d)];
  MPI_Alltoall(send.data(), 1, MPI_INT, recv.data(), 1, MPI_INT, comm);
  recv_begin.assign(static_cast<std::size_t>(ranks) + 1, 0);
  for (int r = 0; r < ranks; ++r) recv_begin[static_cast<std::size_t>(r) + 1] = recv_begin[static_cast<std::size_t>(r)] + recv[static_cast<std::size_t>(r)];
  std::vector<int> base(static_cast<std::size_t>(ranks), 0);  // my first slot on each receiver
  MPI_Alltoall(recv_begin.data(), 1, MPI_INT, base.data(), 1, MPI_INT, comm);
  remote.resize(dest.size());
  for (std::size_t k = 0; k < dest.size(); ++k) {
    const auto d = static_cast<std::size_t>(dest[k]);
    remote[k].rank = dest[k];
    remote[k].index = base[d]++;
  }
  return recv_begin.back();
}

// Morton key of x in the box [lo, lo + extent]: `bits` bits per coordinate, interleaved.
std::uint64_t morton(const Vec3& x, const Vec3& lo, const Vec3& extent, int dim) {
  const int bits = dim == 1 ? 62 : dim == 2 ? 31 : 21;
  const double cells = std::ldexp(1.0, bits) - 1;
  std::array<std::uint64_t, 3> q{};
  for (int k = 0; k < dim; ++k) {
    const double t = extent[k] > 0 ? (x[k] - lo[k]) / extent[k] : 0;
    q[static_cast<std::size_t>(k)] = static_cast<std::uint64_t>(std::clamp(t, 0.0, 1.0) * cells);
  }
  if (dim == 1) return q[0];
  std::uint64_t key = 0;
  for (int b = bits - 1; b >= 0; --b)
    for (int k = 0; k < dim; ++k) key = (key << 1) | ((q[static_cast<std::size_t>(k)] >> b) & 1U);
  return key;
}

Real box_distance(const Vec3& x, const double* box /* lo[3], hi[3] */) {
  Real s = 0;
  for (int k = 0; k < 3; ++k) {
    const Real d = std::max({box[k] - x[k], 0.0, x[k] - box[3 + k]});
    s += d * d;
  }
  return std::sqrt(s);
}

constexpr int boxes_per_rank = 16;  // a Morton range split into compact pieces for the halo test

// Destination rank of every chunk particle: the owner of its place on the curve.
std::vector<int> partition(const Communicator& comm, const std::vector<std::uint64_t>& keys, Index first_id, Index total) {
  const int P = comm.size();
  std::vector<int> dest(keys.size());
  constexpr Index exact_limit = 1 << 20;
  if (total <= exact_limit) {
    // Small clouds: every key on every rank, the curve cut exactly into P equal pieces.
    std::vector<std::uint64_t> all(static_cast<std::size_t>(total));
    std::vector<int> counts(static_cast<std::size_t>(P)), displs(static_cast<std::size_t>(P));
    const std::vector<long long> sizes = gather_over_ranks(comm, static_cast<long long>(keys.size()));
    for (int r = 0, at = 0; r < P; ++r) {
      counts[static_cast<std::size_t>(r)] = static_cast<int>(sizes[static_cast<std::size_t>(r)]);
      displs[static_cast<std::size_t>(r)] = at;
      at += counts[static_cast<std::size_t>(r)];
    }
    MPI_Allgatherv(keys.data(), static_cast<int>(keys.size()), MPI_UINT64_T, all.data(), counts.data(), displs.data(),
                   MPI_UINT64_T, mpi_or_self(comm));
    // Order (key, global id): ties broken by id so that every rank sorts alike.
    std::vector<Index> order(all.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](Index a, Index b) {
      return all[static_cast<std::size_t>(a)] != all[static_cast<std::size_t>(b)] ? all[static_cast<std::size_t>(a)] < all[static_cast<std::size_t>(b)] : a < b;
    });
    std::vector<Index> place(all.size());
    for (std::size_t k = 0; k < order.size(); ++k) place[static_cast<std::size_t>(order[k])] = static_cast<Index>(k);
    for (std::size_t k = 0; k < keys.size(); ++k)
      dest[k] = static_cast<int>(static_cast<long long>(place[static_cast<std::size_t>(first_id) + k]) * P / total);
    return dest;
  }
  // Large clouds: a global histogram of the keys' leading 20 bits, cut at the bucket whose
  // middle crosses r N / P (balance within a bucket, ~N / 10^6 particles).
  constexpr int bucket_bits = 20;
  std::vector<long long> hist(std::size_t{1} << bucket_bits, 0);
  const int shift = 63 - bucket_bits;
  for (std::uint64_t k : keys) ++hist[static_cast<std::size_t>(std::min<std::uint64_t>(k >> shift, hist.size() - 1))];
  sum_over_ranks(comm, hist);
  std::vector<int> rank_of(hist.size());
  long long before = 0;
  for (std::size_t b = 0; b < hist.size(); ++b) {
    const double middle = static_cast<double>(before) + 0.5 * static_cast<double>(hist[b]);
    rank_of[b] = std::min(P - 1, static_cast<int>(middle * P / static_cast<double>(total)));
    before += hist[b];
  }
  for (std::size_t k = 0; k < keys.size(); ++k)
    dest[k] = rank_of[static_cast<std::size_t>(std::min<std::uint64_t>(keys[k] >> shift, hist.size() - 1))];
  return dest;
}
// The chunks' agreement: dimension, normals (on every part or on none), sizes.
struct ChunkShape {
  int dim = 0;
  bool normals = false;
  long long total = 0;
  int first_nonempty = 0;  ///< lowest rank with particles: its spacing and domain count
};

ChunkShape agree_on_chunks(const PointCloud& chunk, Real halo_width, const Communicator& comm) {
  const int P = comm.size();
  collective(comm, [&] {
    check<ConfigError>(std::isfinite(halo_width) && halo_width > 0, "the halo width must be positive and finite, got ",
                       halo_width);
    if (chunk.size() > 0) validate(chunk);
  });
  const auto dims = gather_over_ranks(comm, chunk.size() > 0 ? chunk.dim : 0);
  const auto normals = gather_over_ranks(comm, chunk.size() > 0 ? (chunk.has_normals() ? 1 : 0) : -1);
  ChunkShape shape;
  shape.total = sum_over_ranks(comm, static_cast<long long>(chunk.size()));
  collective(comm, [&] {
    int dim = 0, with_normals = -1;
    for (int r = 0; r < P; ++r) {
      const auto sr = static_cast<std::size_t>(r);
      if (dims[sr] == 0) continue;
      check<InputError>(dim == 0 || dims[sr] == dim, "the cloud's parts disagree on the dimension: ", dim, "D and ",
                        dims[sr], "D (rank ", r, ")");
      check<InputError>(with_normals < 0 || normals[sr] == with_normals, "the cloud's parts disagree on normals: rank ",
                        r, normals[sr] ? " has them" : " has none");
      dim = static_cast<int>(dims[sr]);
      with_normals = static_cast<int>(normals[sr]);
    }
    check<InputError>(shape.total > 0, "the distributed cloud has no particle");
    check<ConfigError>(shape.total >= P, "more ranks (", P, ") than particles (", shape.total, "): run with at most ",
                       shape.total, " ranks");
    check<ConfigError>(shape.total < std::numeric_limits<Index>::max(), "the cloud has ", shape.total,
                       " particles, more than the ", std::numeric_limits<Index>::max(), " a 32-bit index can number");
  });
  for (int r = P - 1; r >= 0; --r)
    if (dims[static_cast<std::size_t>(r)] > 0) {
      shape.dim = static_cast<int>(dims[static_cast<std::size_t>(r)]);
      shape.normals = normals[static_cast<std::size_t>(r)] == 1;
      shape.first_nonempty = r;
    }
  return shape;
}

// Spacing and domain from the lowest rank with particles: an empty part (a default
// PointCloud) carries neither.
void broadcast_domain(const PointCloud& chunk, int source, const Communicator& comm, PointCloud& local) {
  const Domain& d = chunk.domain;
  std::array<double, 16> packed{static_cast<double>(static_cast<int>(d.shape)), static_cast<double>(d.dim),
                                d.lo[0], d.lo[1], d.lo[2], d.hi[0], d.hi[1], d.hi[2], d.centre[0], d.centre[1],
                                d.centre[2], d.radius, chunk.spacing, d.periodic[0] ? 1.0 : 0.0,
                                d.periodic[1] ? 1.0 : 0.0, d.periodic[2] ? 1.0 : 0.0};
  MPI_Bcast(packed.data(), static_cast<int>(packed.size()), MPI_DOUBLE, source, mpi_or_self(comm));
  Domain& out = local.domain;
  out.shape = static_cast<Domain::Shape>(static_cast<int>(packed[0]));
  out.dim = static_cast<int>(packed[1]);
  out.lo = Vec3(packed[2], packed[3], packed[4]);
  out.hi = Vec3(packed[5], packed[6], packed[7]);
  out.centre = Vec3(packed[8], packed[9], packed[10]);
  out.radius = packed[11];
  local.spacing = packed[12];
  for (std::size_t k = 0; k < 3; ++k) out.periodic[k] = packed[13 + k] != 0;
}

// What travels with a particle: its global number, position, tag and normal, and on a
// periodic box the shift code of the image it is (no_shift: the particle itself).
struct Payload {
  std::vector<Index> id;
  std::vector<double> xyz, nrm;
  std::vector<std::uint8_t> tag, shift;
  bool normals;  ///< (nrm is empty on an empty part even when the cloud has normals)
  Payload(std::size_t n, bool with_normals)
      : id(n), xyz(3 * n), nrm(with_normals ? 3 * n : 0), tag(n), shift(n, no_shift), normals(with_normals) {}
  std::size_t size() const { return id.size(); }
  Vec3 position(std::size_t k) const { return {xyz[3 * k], xyz[3 * k + 1], xyz[3 * k + 2]}; }
  Vec3 normal(std::size_t k) const { return {nrm[3 * k], nrm[3 * k + 1], nrm[3 * k + 2]}; }
  void copy(std::size_t to, const Payload& from, std::size_t k) {
    id[to] = from.id[k];
    tag[to] = from.tag[k];
    shift[to] = from.shift[k];
    for (std::size_t c = 0; c < 3; ++c) {
      xyz[3 * to + c] = from.xyz[3 * k + c];
      if (normals) nrm[3 * to + c] = from.nrm[3 * k + c];
    }
  }
  // Leaves' payload to the roots of `sf` (REPLACE).
  Payload sent(PetscSF sf, std::size_t roots) const {
    Payload out(roots, normals);
    reduce(sf, id.data(), out.id.data());
    reduce(sf, xyz.data(), out.xyz.data(), 3);
    reduce(sf, tag.data(), out.tag.data());
    reduce(sf, shift.data(), out.shift.data());
    if (normals) reduce(sf, nrm.data(), out.nrm.data(), 3);
    return out;
  }
};

Payload chunk_payload(const PointCloud& chunk, Index first_id, bool normals) {
  Payload p(static_cast<std::size_t>(chunk.size()), normals);
  for (std::size_t k = 0; k < p.size(); ++k) {
    p.id[k] = first_id + static_cast<Index>(k);
    for (std::size_t c = 0; c < 3; ++c) {
      p.xyz[3 * k + c] = chunk.positions[k][static_cast<int>(c)];
      if (normals) p.nrm[3 * k + c] = chunk.normals[k][static_cast<int>(c)];
    }
    p.tag[k] = static_cast<std::uint8_t>(chunk.tags[k]);
  }
  return p;
}

// The (owned particle, receiving rank, shift) triples of the halo: owned particles, or their
// periodic images, within halo_width of one of another rank's boxes (of the rank's own boxes
// for an image), each box a stretch of that rank's part of the curve.
void halo_pairs(const Payload& own, const Vec3& lo, const Vec3& hi, const Domain& domain, Real halo_width, MPI_Comm comm,
                int me, int P, std::vector<std::size_t>& pair_particle, std::vector<int>& pair_rank,
                std::vector<std::uint8_t>& pair_shift) {
  const int dim = domain.dim;
  const std::size_t n_own = own.size();
  std::vector<Index> by_key(n_own);
  std::iota(by_key.begin(), by_key.end(), 0);
  {
    std::vector<std::uint64_t> own_key(n_own);
    for (std::size_t k = 0; k < n_own; ++k) own_key[k] = morton(own.position(k), lo, hi - lo, dim);
    std::sort(by_key.begin(), by_key.end(), [&](Index a, Index b) {
      const auto sa = static_cast<std::size_t>(a), sb = static_cast<std::size_t>(b);
      return own_key[sa] != own_key[sb] ? own_key[sa] < own_key[sb] : a < b;
    });
  }
  std::vector<double> boxes(6 * boxes_per_rank), all_boxes(6 * boxes_per_rank * static_cast<std::size_t>(P));
  for (int b = 0; b < boxes_per_rank; ++b) {
    double* box = &boxes[6 * static_cast<std::size_t>(b)];
    for (int c = 0; c < 3; ++c) {
      box[c] = std::numeric_limits<double>::infinity();
      box[3 + c] = -std::numeric_limits<double>::infinity();
    }
    const std::size_t from = n_own * static_cast<std::size_t>(b) / boxes_per_rank,
                      to = n_own * static_cast<std::size_t>(b + 1) / boxes_per_rank;
    for (std::size_t k = from; k < to; ++k) {
      const Vec3 x = own.position(static_cast<std::size_t>(by_key[k]));
      for (int c = 0; c < 3; ++c) {
        box[c] = std::min(box[c], x[c]);
        box[3 + c] = std::max(box[3 + c], x[c]);
      }
    }
  }
  MPI_Allgather(boxes.data(), 6 * boxes_per_rank, MPI_DOUBLE, all_boxes.data(), 6 * boxes_per_rank, MPI_DOUBLE, comm);
  const bool periodic = domain.any_periodic();
  for (std::size_t k = 0; k < n_own; ++k) {
    const std::vector<std::uint8_t> codes =
        periodic ? image_codes(domain, dim, own.position(k), halo_width) : std::vector<std::uint8_t>{no_shift};
    for (const std::uint8_t code : codes) {
      const Vec3 x = own.position(k) + periodic_shift(domain, code);
      for (int q = 0; q < P; ++q) {
        if (q == me && code == no_shift) continue;
        bool near = false;
        for (int b = 0; b < boxes_per_rank && !near; ++b)
          near = box_distance(x, &all_boxes[6 * (static_cast<std::size_t>(q) * boxes_per_rank + static_cast<std::size_t>(b))]) <= halo_width;
        if (near) {
          pair_particle.push_back(k);
          pair_rank.push_back(q);
          pair_shift.push_back(code);
        }
      }
    }
  }
}

// Where periodic_images puts an image among its original's (the loops over x, y, z, each
// taking shift 0, +1, -1 in that order): the local arrays order images as the serial periodic
// partition does, so that every row lists its columns in the serial order (VRSPH's NNLS may
// pick another of its optimal vertices in another column order).
int image_rank(std::uint8_t code) {
  int key = 0;
  for (int k = 0; k < 3; ++k) {
    const int s = axis_shift(code, k);
    key = key * 3 + (s == 0 ? 0 : s == 1 ? 1 : 2);
  }
  return key;
}

// Local arrays: owned and halo particles by global id, then a periodic box's images (by their
// originals' ids). Returns each halo slot's local index.
std::vector<Index> local_arrays(const Payload& own, const Payload& halo, DistributedCloud& dc, CloudExchange& ex) {
  struct Entry {
    Index id;
    std::size_t slot;  // arrival slot (owned) or halo slot
    bool owned;
    int image;  // -1: the particle itself; else image_rank of its shift
  };
  std::vector<Entry> entries;
  entries.reserve(own.size() + halo.size());
  for (std::size_t k = 0; k < own.size(); ++k) entries.push_back({own.id[k], k, true, -1});
  for (std::size_t k = 0; k < halo.size(); ++k)
    entries.push_back({halo.id[k], k, false, halo.shift[k] == no_shift ? -1 : image_rank(halo.shift[k])});
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    if ((a.image >= 0) != (b.image >= 0)) return a.image < 0;
    if (a.id != b.id) return a.id < b.id;
    return a.image < b.image;  // (one entry per id and shift)
  });
  const std::size_t n_local = entries.size();
  const bool normals = own.normals;
  dc.global_id.resize(n_local);
  dc.owned.resize(n_local);
  dc.local.positions.resize(n_local);
  dc.local.tags.resize(n_local);
  if (normals) dc.local.normals.resize(n_local);
  ex.arrival_to_local.resize(own.size());
  std::vector<Index> halo_slot_to_local(halo.size());
  for (std::size_t i = 0; i < n_local; ++i) {
    const Entry& e = entries[i];
    const Payload& src = e.owned ? own : halo;
    dc.global_id[i] = e.id;
    dc.owned[i] = e.owned;
    dc.local.positions[i] = src.position(e.slot);
    dc.local.tags[i] = static_cast<Tag>(src.tag[e.slot]);
    if (normals) dc.local.normals[i] = src.normal(e.slot);
    (e.owned ? ex.arrival_to_local[e.slot] : halo_slot_to_local[e.slot]) = static_cast<Index>(i);
  }
  dc.owned_count = static_cast<Index>(own.size());
  dc.stats.owned = dc.owned_count;
  dc.stats.halo = static_cast<Index>(halo.size());
  return halo_slot_to_local;
}
}  // namespace

DistributedCloud distribute(const PointCloud& chunk, Real halo_width, const Communicator& comm) {
  const auto t0 = std::chrono::steady_clock::now();
  detail::start_petsc();  // the star forests are PETSc's (a serial Communicator has not started it)
  DistributedCloud dc;
  dc.comm = comm;
  dc.halo_width = halo_width;
  const int P = comm.size(), me = comm.rank();
  const ChunkShape shape = agree_on_chunks(chunk, halo_width, comm);
  dc.global_size = static_cast<Index>(shape.total);
  const Index first_id = static_cast<Index>(offset_over_ranks(comm, chunk.size()));
  dc.local.dim = shape.dim;
  broadcast_domain(chunk, shape.first_nonempty, comm, dc.local);

  // The curve: keys in the global bounding box.
  Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::infinity()), hi = -lo;
  for (const Vec3& x : chunk.positions) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  for (int k = 0; k < 3; ++k) {
    lo[k] = min_over_ranks(comm, lo[k]);
    hi[k] = max_over_ranks(comm, hi[k]);
  }
  std::vector<std::uint64_t> keys(chunk.positions.size());
  for (std::size_t k = 0; k < keys.size(); ++k) keys[k] = morton(chunk.positions[k], lo, hi - lo, shape.dim);

  // Migration to the owners.
  auto ex = std::make_shared<CloudExchange>();
  ex->comm = mpi_or_self(comm);
  ex->chunk_size = chunk.size();
  const std::vector<int> dest = partition(comm, keys, first_id, dc.global_size);
  std::vector<PetscSFNode> remote;
  std::vector<int> recv_begin;
  const Index arrived = slots_for(ex->comm, P, dest, remote, recv_begin);
  ex->migration = make_sf(ex->comm, arrived, remote, nullptr);
  const Payload own = chunk_payload(chunk, first_id, shape.normals).sent(ex->migration, static_cast<std::size_t>(arrived));
  // Payload per particle: its number, tag, position and normal.
  const long long particle_bytes = static_cast<long long>(sizeof(Index)) + 1 + (shape.normals ? 48 : 24);
  for (const int d : dest)
    if (d != me) dc.stats.migration_bytes += particle_bytes;
  collective(comm, [&] {
    check<ConfigError>(arrived > 0, "rank ", me, " of ", P, " owns no particle after the partition along the "
                       "space-filling curve (too many ranks for ", shape.total, " particles, or coincident particles): "
                       "use fewer ranks");
  });

  // Halo: owned particles within halo_width of another rank's pieces of the curve.
  std::vector<std::size_t> pair_particle;
  std::vector<int> pair_rank;
  std::vector<std::uint8_t> pair_shift;
  const Domain& domain = dc.local.domain;
  if (domain.any_periodic())
    collective(comm, [&] { check_image_width(domain, shape.dim, halo_width, "the halo across the ranks reaches"); });
  halo_pairs(own, lo, hi, domain, halo_width, ex->comm, me, P, pair_particle, pair_rank, pair_shift);
  const Index halo_count = slots_for(ex->comm, P, pair_rank, remote, recv_begin);
  PetscSF push = make_sf(ex->comm, halo_count, remote, nullptr);
  struct Destroy {
    PetscSF* sf;
    ~Destroy() { PetscSFDestroy(sf); }
  } destroy_push{&push};
  const std::size_t n_pairs = pair_particle.size(), n_halo = static_cast<std::size_t>(halo_count);
  {
    std::vector<int> ranks_sent(pair_rank);
    std::sort(ranks_sent.begin(), ranks_sent.end());
    dc.stats.halo_messages = static_cast<int>(std::unique(ranks_sent.begin(), ranks_sent.end()) - ranks_sent.begin());
  }
  dc.stats.halo_bytes = static_cast<long long>(n_pairs) * (particle_bytes + static_cast<long long>(sizeof(Index)));
  Payload pairs(n_pairs, shape.normals);
  for (std::size_t p = 0; p < n_pairs; ++p) {
    pairs.copy(p, own, pair_particle[p]);
    pairs.shift[p] = pair_shift[p];
    if (pair_shift[p] == no_shift) continue;
    const Vec3 s = periodic_shift(domain, pair_shift[p]);
    for (std::size_t c = 0; c < 3; ++c) pairs.xyz[3 * p + c] += s[static_cast<int>(c)];
  }
  const Payload halo = pairs.sent(push, n_halo);
  const std::vector<Index> halo_slot_to_local = local_arrays(own, halo, dc, *ex);

  // The ghost-update graph: each halo entry's owner and its place in the owner's local arrays.
  std::vector<Index> send_local(n_pairs), halo_owner_local(n_halo);
  for (std::size_t p = 0; p < n_pairs; ++p) send_local[p] = ex->arrival_to_local[pair_particle[p]];
  reduce(push, send_local.data(), halo_owner_local.data());
  std::vector<PetscSFNode> halo_remote(n_halo);
  std::vector<PetscInt> halo_leaf(n_halo);
  for (int r = 0; r < P; ++r)
    for (int s = recv_begin[static_cast<std::size_t>(r)]; s < recv_begin[static_cast<std::size_t>(r) + 1]; ++s) {
      const auto ss = static_cast<std::size_t>(s);
      halo_remote[ss].rank = r;
      halo_remote[ss].index = halo_owner_local[ss];
      halo_leaf[ss] = halo_slot_to_local[ss];
    }
  ex->halo = make_sf(ex->comm, static_cast<Index>(dc.local.size()), halo_remote, &halo_leaf);
  dc.exchange = std::move(ex);
  dc.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return dc;
}

namespace {
template <class T>
void halo_update(const DistributedCloud& dc, T* values) {
  if (!dc.exchange) return;
  const std::vector<T> roots(values, values + dc.local_size());
  bcast(dc.exchange->halo, roots.data(), values);
}
}  // namespace

void update_halo(const DistributedCloud& dc, Field& v) {
  check<InputError>(v.size() == dc.local_size(), "update_halo: ", v.size(), " values for ", dc.local_size(), " particles");
  halo_update(dc, v.data());
}
void update_halo(const DistributedCloud& dc, std::vector<Index>& v) {
  check<InputError>(static_cast<Index>(v.size()) == dc.local_size(), "update_halo: size mismatch");
  halo_update(dc, v.data());
}
void update_halo(const DistributedCloud& dc, std::vector<char>& v) {
  check<InputError>(static_cast<Index>(v.size()) == dc.local_size(), "update_halo: size mismatch");
  halo_update(dc, v.data());
}

Field chunk_to_local(const DistributedCloud& dc, const Field& chunk_values) {
  const CloudExchange& ex = *dc.exchange;
  // Agreed before the exchange: a rank that stopped here would leave the others waiting in it.
  collective(dc.comm, [&] {
    check<InputError>(chunk_values.size() == ex.chunk_size, "a field has ", chunk_values.size(), " values for the ",
                      ex.chunk_size, " particles of this rank's part of the cloud");
  });
  std::vector<double> arrived(ex.arrival_to_local.size());
  reduce(ex.migration, chunk_values.data(), arrived.data());
  Field local = Field::Zero(dc.local_size());
  for (std::size_t k = 0; k < arrived.size(); ++k) local[ex.arrival_to_local[k]] = arrived[k];
  update_halo(dc, local);
  return local;
}

Eigen::MatrixXd chunk_to_local(const DistributedCloud& dc, const Eigen::MatrixXd& chunk_values) {
  Eigen::MatrixXd local(dc.local_size(), chunk_values.cols());
  for (Index c = 0; c < chunk_values.cols(); ++c) local.col(c) = chunk_to_local(dc, Field(chunk_values.col(c)));
  return local;
}

Field local_to_chunk(const DistributedCloud& dc, const Field& local_values) {
  const CloudExchange& ex = *dc.exchange;
  collective(dc.comm, [&] {
    check<InputError>(local_values.size() == dc.local_size(), "local_to_chunk: ", local_values.size(), " values for ",
                      dc.local_size(), " particles");
  });
  std::vector<double> arrived(ex.arrival_to_local.size());
  for (std::size_t k = 0; k < arrived.size(); ++k) arrived[k] = local_values[ex.arrival_to_local[k]];
  Field chunk = Field::Zero(ex.chunk_size);
  bcast(ex.migration, arrived.data(), chunk.data());
  return chunk;
}

std::vector<char> reach_over_ranks(const DistributedCloud& dc, std::span<const Index> offsets,
                                   std::span<const Index> targets, std::vector<char> seeds) {
  // Backward edges j -> i (i reaches j): a node is reached when it is a seed or has an edge
  // into a reached node. Rounds: halo flags from the owners, then a local search; until no
  // rank changes. Each round crosses one more partition boundary.
  const Index n = dc.local_size();
  std::vector<Index> rev_offset(static_cast<std::size_t>(n) + 1, 0), rev;
  for (Index i = 0; i < n; ++i)
    for (Index k = offsets[static_cast<std::size_t>(i)]; k < offsets[static_cast<std::size_t>(i) + 1]; ++k)
      ++rev_offset[static_cast<std::size_t>(targets[static_cast<std::size_t>(k)]) + 1];
  for (std::size_t j = 0; j < static_cast<std::size_t>(n); ++j) rev_offset[j + 1] += rev_offset[j];
  rev.resize(static_cast<std::size_t>(rev_offset.back()));
  {
    std::vector<Index> fill(rev_offset.begin(), rev_offset.end() - 1);
    for (Index i = 0; i < n; ++i)
      for (Index k = offsets[static_cast<std::size_t>(i)]; k < offsets[static_cast<std::size_t>(i) + 1]; ++k)
        rev[static_cast<std::size_t>(fill[static_cast<std::size_t>(targets[static_cast<std::size_t>(k)])]++)] = i;
  }
  for (;;) {
    update_halo(dc, seeds);
    std::vector<Index> queue;
    for (Index i = 0; i < n; ++i)
      if (seeds[static_cast<std::size_t>(i)]) queue.push_back(i);
    bool changed = false;
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const auto j = static_cast<std::size_t>(queue[head]);
      for (Index k = rev_offset[j]; k < rev_offset[j + 1]; ++k) {
        const auto i = static_cast<std::size_t>(rev[static_cast<std::size_t>(k)]);
        if (!seeds[i]) {
          seeds[i] = 1;
          changed = changed || dc.owned[i];
          queue.push_back(static_cast<Index>(i));
        }
      }
    }
    if (!any_rank(dc.comm, changed)) break;
  }
  return seeds;
}

}  // namespace vrsph
