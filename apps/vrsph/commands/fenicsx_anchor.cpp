// SPDX-License-Identifier: BSD-3-Clause
#include "fenicsx_anchor.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <unistd.h>
#include <vrsph/config.hpp>
#include <vrsph/core/error.hpp>
#include <vrsph/core/features.hpp>
#include "../cli_common.hpp"
#ifdef _OPENMP
#include <omp.h>
#endif
#if VRSPH_HAVE_JSON
#include <nlohmann/json.hpp>
#endif

namespace vrsph::cli {

namespace {
// Runs the peer's script as __main__ and then prints, on rank 0, the summed peak resident
// memory of all its ranks: the memory a refinement sweep extrapolates before it asks for a
// larger run. (The script itself reports sizes, errors and times, not memory.)
constexpr const char* peak_memory_wrapper = R"PY(
import json, os, resource, runpy, sys
# The script imports scipy.spatial inside its timed region where it meshes points (--points,
# --perturbed); a user's session has it loaded, so it is imported here first, and only then.
if "--points" in sys.argv or "--perturbed" in sys.argv:
    try:
        import scipy.spatial
    except ImportError:
        pass
script = sys.argv[1]
sys.argv = sys.argv[1:]
try:
    runpy.run_path(script, run_name="__main__")
except SystemExit as e:
    if e.code not in (None, 0):
        raise
kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
# The ranks' sum where the script runs on MPI (FEniCSx imports mpi4py): a script that did not,
# alone, is its own sum (importing mpi4py here would start MPI only to count one rank).
MPI = sys.modules.get("mpi4py.MPI")
if MPI is None and int(os.environ.get("OMPI_COMM_WORLD_SIZE", "1")) > 1:
    try:
        from mpi4py import MPI
    except ImportError:
        MPI = None
rank = 0
if MPI is not None:
    kib, rank = MPI.COMM_WORLD.allreduce(kib), MPI.COMM_WORLD.rank
if rank == 0:
    print(json.dumps({"peak_rss_kib": kib}), flush=True)
)PY";

int machine_cores() {
#ifdef _OPENMP
  return omp_get_num_procs();
#else
  return 1;
#endif
}

// The line of the peer's error output that says why it failed: Python's exception line
// ("ModuleNotFoundError: No module named 'dolfinx'") where there is one, else the last line
// that says something (mpirun frames its own messages in lines of dashes and ends them with
// "Exit code: 1", which alone says nothing).
std::string cause_line(const std::string& path) {
  std::ifstream in(path);
  std::string line, last, exception;
  while (std::getline(in, line)) {
    if (!std::any_of(line.begin(), line.end(), [](unsigned char c) { return std::isalpha(c); })) continue;
    last = line;
    const auto colon = line.find(": ");
    const std::string head = line.substr(0, colon);
    if (colon != std::string::npos && !head.empty() && std::isalpha(static_cast<unsigned char>(head.front())) &&
        (head.ends_with("Error") || head.ends_with("Exception")) &&
        std::all_of(head.begin(), head.end(), [](unsigned char c) { return std::isalnum(c) || c == '_' || c == '.'; }))
      exception = line;
  }
  return exception.empty() ? last : exception;
}

// The module Python could not import, from a cause line "ModuleNotFoundError: No module named
// 'x'" (empty otherwise).
std::string missing_module(const std::string& cause) {
  const std::string key = "No module named '";
  const auto at = cause.find(key);
  if (at == std::string::npos) return {};
  const auto begin = at + key.size();
  const auto end = cause.find('\'', begin);
  return end == std::string::npos ? std::string() : cause.substr(begin, end - begin);
}

constexpr const char* peer_packages = "python3-dolfinx-real python3-petsc4py python3-mpi4py python3-scipy";

// Installs the peer's Debian packages, as the README's commands install ours: only as root, with
// apt-get on PATH, once per run, and not when VRSPH_NO_INSTALL is set. The output goes to
// stderr (stdout carries the tables). True when apt-get succeeded.
bool install_peer_packages(const std::string& missing) {
  static bool tried = false;
  if (tried || std::getenv("VRSPH_NO_INSTALL") != nullptr || ::geteuid() != 0 ||
      std::system("command -v apt-get >/dev/null 2>&1") != 0)
    return false;
  tried = true;
  std::fprintf(stderr, "vrsph: the FEniCSx peer is not installed (python3 has no module '%s'); installing %s\n",
               missing.c_str(), peer_packages);
  const std::string install =
      std::string("DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends ") + peer_packages + " >&2";
  if (std::system(install.c_str()) == 0) return true;
  // A fresh machine's package lists may be missing or stale.
  return std::system("DEBIAN_FRONTEND=noninteractive apt-get update -qq >&2") == 0 && std::system(install.c_str()) == 0;
}

std::string describe(int degree, int cells, AnchorMesh mesh) {
  return detail::concat("P", degree, mesh == AnchorMesh::SamePoints ? std::string(" on our points")
                                                                    : detail::concat(", ", cells, " cells per direction"));
}
}  // namespace

void add_anchor_options(CLI::App& cmd, AnchorOptions& o, const std::string& what) {
  cmd.add_option("--anchor", o.anchor, what);
  cmd.add_option("--anchor-degree", o.degrees, "The peer's Lagrange degrees, comma-separated (1, 2, 3)")
      ->capture_default_str();
  cmd.add_option("--anchor-ranks", o.ranks, "The peer's MPI ranks (0: as many as vrsph's threads; at most the cores)")
      ->capture_default_str();
  cmd.add_option("--anchor-script", o.script,
                 "The peer's script (default: $VRSPH_ANCHOR_DIR/fenicsx_ex5.py, else ../shared/anchors next to the "
                 "source tree)");
}

void reject_peer_options_without_peer(const CLI::App& cmd, const AnchorOptions& o) {
  for (const char* option : {"--anchor-degree", "--anchor-ranks", "--anchor-script"})
    check<ConfigError>(!o.anchor.empty() || cmd.count(option) == 0, option, " applies to the peer: add --anchor fenicsx");
}

std::string to_string(AnchorMesh mesh) {
  switch (mesh) {
    case AnchorMesh::Structured: return "lattice";
    case AnchorMesh::OwnPerturbed: return "own perturbed";
    case AnchorMesh::SamePoints: return "same points";
  }
  return "?";
}

std::string fenicsx_script(const std::string& option) {
  std::string script = option;
  if (script.empty()) {
    if (const char* dir = std::getenv("VRSPH_ANCHOR_DIR"))
      script = std::string(dir) + "/fenicsx_ex5.py";
    else
      script = std::string(VRSPH_SOURCE_DIR) + "/../shared/anchors/fenicsx_ex5.py";
  }
  check<IoError>(std::filesystem::is_regular_file(script), "the FEniCSx anchor script '", script,
                 "' does not exist (--anchor-script or VRSPH_ANCHOR_DIR)");
  return script;
}

int anchor_ranks(int requested) {
  check<ConfigError>(requested >= 0, "--anchor-ranks must be >= 0 (0: as many as vrsph's threads), got ", requested);
  int ranks = requested;
#ifdef _OPENMP
  if (ranks == 0) ranks = omp_get_max_threads();
#endif
  ranks = std::max(1, ranks);
  // Under mpirun (vrsph --ranks P) each rank sees its own share of the cores, and a peer on
  // several ranks would need an mpirun inside vrsph's own.
  check<ConfigError>(ranks == 1 || !Communicator::launched_in_parallel(), "--anchor-ranks ", ranks,
                     " with vrsph itself on ", communicator().size(), " MPI ranks: the peer cannot start its own mpirun "
                     "inside vrsph's; give --anchor-ranks 1, or run vrsph in one process (--threads ", ranks,
                     ") beside the peer on ", ranks, " ranks");
  const int cores = machine_cores();
  check<ConfigError>(ranks <= cores, "--anchor-ranks ", ranks, " is more than this machine's ", cores,
                     " cores: the peer runs on the same cores as vrsph, not oversubscribed");
  check<ConfigError>(ranks == 1 || std::system("command -v mpirun >/dev/null 2>&1") == 0,
                     "--anchor-ranks ", ranks, " needs mpirun (Debian's openmpi-bin), which is not on PATH");
  return ranks;
}

AnchorSetup anchor_setup(const AnchorOptions& o, int dim) {
  // The peer reports in JSON lines: refused before any run when they cannot be read.
  require_part("JSON", "--anchor fenicsx (the peer's reports are JSON)");
  const int ranks = anchor_ranks(o.ranks);
  return {fenicsx_script(o.script), dim, ranks};
}

std::vector<int> parse_anchor_degrees(const std::string& text) {
  std::vector<int> degrees = parse_int_list(text, "--anchor-degree");
  for (int k : degrees)
    check<ConfigError>(k >= 1 && k <= 3, "--anchor-degree takes Lagrange degrees 1, 2 or 3, got ", k);
  for (std::size_t i = 0; i < degrees.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      check<ConfigError>(degrees[i] != degrees[j], "--anchor-degree lists P", degrees[i], " twice");
  return degrees;
}

int anchor_cells(int n, int degree) {
  return std::max(1, static_cast<int>(std::lround(static_cast<double>(n) / degree)));
}

AnchorMesh anchor_mesh(const AnchorSetup& setup, bool perturbed, int degree) {
  // The peer meshes a point set (scipy's Delaunay) in 2D and in serial only (under mpirun
  // it aborts), and only its P1 nodes coincide with the points.
  if (!perturbed || setup.dim != 2 || setup.ranks > 1) return AnchorMesh::Structured;
  return degree == 1 ? AnchorMesh::SamePoints : AnchorMesh::OwnPerturbed;
}

AnchorRun run_anchor(const AnchorSetup& setup, int degree, int cells, AnchorMesh mesh, const std::string& points_csv) {
  check<ConfigError>(mesh != AnchorMesh::SamePoints || !points_csv.empty(), "the peer on our points needs the cloud file");
  std::string args = mesh == AnchorMesh::SamePoints ? " --points " + shell_quote(points_csv) : " " + std::to_string(cells);
  if (mesh == AnchorMesh::OwnPerturbed) args += " --perturbed";
  args += " --degree " + std::to_string(degree) + " --dim " + std::to_string(setup.dim);
  const std::string launcher =
      setup.ranks > 1 ? "mpirun --allow-run-as-root -np " + std::to_string(setup.ranks) + " " : std::string();
  const TemporaryFile errors("vrsph-anchor", ".err");
  // Under our own mpirun the peer must not see the launcher's variables (it would join our job).
  const std::string cmd = "for v in $(env | grep -o '^\\(OMPI\\|PMIX\\|PMI\\)[A-Za-z0-9_]*'); do unset \"$v\"; done; "
                          "OMP_NUM_THREADS=1 " + launcher + shell_quote(python_interpreter()) + " -c " +
                          shell_quote(peak_memory_wrapper) + " " + shell_quote(setup.script) + args + " 2>" +
                          shell_quote(errors.path());
  const std::string what = describe(degree, cells, mesh) + ", " + std::to_string(setup.dim) + "D, " +
                           std::to_string(setup.ranks) + (setup.ranks == 1 ? " rank" : " ranks");
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(::popen(cmd.c_str(), "r"), ::pclose);
  check<IoError>(pipe != nullptr, "could not start the FEniCSx anchor (", setup.script, ")");
  std::string out;
  std::array<char, 4096> buf{};
  while (std::fgets(buf.data(), static_cast<int>(buf.size()), pipe.get())) out += buf.data();
  const int rc = ::pclose(pipe.release());
  if (rc != 0 || out.empty()) {
    const std::string cause = cause_line(errors.path());
    const std::string module = missing_module(cause);
    if (!module.empty()) {
      if (install_peer_packages(module)) return run_anchor(setup, degree, cells, mesh, points_csv);
      throw IoError(detail::concat("the FEniCSx anchor is not installed: python3 has no module '", module,
                                   "' (install it: apt-get install -y --no-install-recommends ", peer_packages, ")"));
    }
    throw IoError(detail::concat("the FEniCSx anchor failed (", what, "; ", setup.script, ")",
                                 cause.empty() ? std::string() : ": " + cause, " (it needs Debian's ", peer_packages,
                                 ")"));
  }
  AnchorRun run;
  run.degree = degree;
  run.cells = cells;
  run.mesh = mesh;
#if VRSPH_HAVE_JSON
  bool found = false;
  std::istringstream lines(out);
  std::string line;
  try {
    while (std::getline(lines, line)) {
      if (line.empty() || line.front() != '{') continue;
      const auto j = nlohmann::json::parse(line);
      if (j.contains("peak_rss_kib")) {
        run.peak_bytes = 1024.0 * j.at("peak_rss_kib").get<double>();
      } else if (!found) {
        run.seconds_total = j.at("total").get<double>();
        run.error_inf = j.at("error_inf").get<double>();
        run.iterations = j.at("iterations").get<int>();
        run.nodes = j.at("nodes").get<long long>();
        if (j.contains("n") && j.at("n").is_number_integer()) run.cells = j.at("n").get<int>();
        found = j.at("reason").get<int>() > 0 || !j.contains("reason");
        check<IoError>(found, "the FEniCSx anchor's solver did not converge (", what, ", KSP reason ",
                       j.at("reason").get<int>(), ")");
      }
    }
  } catch (const nlohmann::json::exception& e) {
    throw IoError(detail::concat("the FEniCSx anchor (", what, ", ", setup.script,
                                 ") printed a line that is not its JSON result: ", e.what()));
  }
#else
  const bool found = false;  // not reached: anchor_setup required the part
#endif
  check<IoError>(found, "the FEniCSx anchor (", what, ", ", setup.script,
                 ") did not print its JSON line (nodes, total, error_inf, iterations)");
  check<IoError>(std::isfinite(run.error_inf) && std::isfinite(run.seconds_total),
                 "the FEniCSx anchor (", what, ") reported a non-finite error or time");
  return run;
}

void warm_up_anchor(const AnchorSetup& setup, const std::vector<int>& degrees) {
  // Forms are compiled per degree and dimension (cached on disk); the mesh kind does not
  // matter, so a lattice is enough, and two cells keep the run short.
  for (int k : degrees) (void)run_anchor(setup, k, 2, AnchorMesh::Structured);
}

}  // namespace vrsph::cli
