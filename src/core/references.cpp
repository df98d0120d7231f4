// SPDX-License-Identifier: BSD-3-Clause
// The bibliography. The four papers' identifiers were checked against arXiv and the
// publishers' pages reachable from this project (docs/references.md records what could not be).
#include <vrsph/core/references.hpp>

#include <algorithm>

namespace vrsph {

std::string Reference::citation() const {
  std::string out = std::string(authors) + ", \"" + std::string(title) + "\", " + std::string(venue) + " (" +
                    std::to_string(year) + ")";
  if (!identifier.empty()) out += ", " + std::string(identifier);
  return out;
}

const std::vector<Reference>& references() {
  static const std::vector<Reference> all = {
      {"QW", "Z. Qiao, Y. Wei",
       "Convergence analysis of SPH method on irregular particle distributions for the Poisson equation", "preprint",
       2025, "arXiv:2503.15188"},
      {"AAR", "D. Asprone, F. Auricchio, A. Reali",
       "Particle methods for a 1D elastic model problem: error analysis and development of a second-order accurate "
       "formulation",
       "Computer Modeling in Engineering & Sciences (CMES) 62(1), 1-21", 2010, ""},
      {"SPE", "A. A. Lukyanov, C. Vuik",
       "A stable SPH discretization of the elliptic operator with heterogeneous coefficients",
       "preprint; journal version Elsevier 2020", 2017, "arXiv:1711.11351"},
      {"IM", "Y. Imoto", "Truncation error estimates of approximate operators in a generalized particle method",
       "Japan Journal of Industrial and Applied Mathematics 37, 565-598", 2020, "doi:10.1007/s13160-020-00407-1, arXiv:1907.03232"},
      {"CBC", "J. K. Chen, J. E. Beraun, T. C. Carney",
       "A corrective smoothed particle method for boundary value problems in heat conduction",
       "International Journal for Numerical Methods in Engineering 46, 231-252", 1999,
       "doi:10.1002/(SICI)1097-0207(19990920)46:2<231::AID-NME672>3.0.CO;2-K"},
      {"CB", "J. K. Chen, J. E. Beraun",
       "A generalized smoothed particle hydrodynamics method for nonlinear dynamic problems",
       "Computer Methods in Applied Mechanics and Engineering 190, 225-239", 2000, ""},
      {"LL", "M. B. Liu, G. R. Liu", "Restoring particle consistency in smoothed particle hydrodynamics",
       "Applied Numerical Mathematics 56, 19-36", 2006, "doi:10.1016/j.apnum.2005.02.012"},
      {"HLLP", "C. Huang, J. M. Lei, M. B. Liu, X. Y. Peng",
       "A kernel gradient free (KGF) SPH method", "International Journal for Numerical Methods in Fluids 78, 691-707",
       2015, ""},
  };
  return all;
}

std::vector<Reference> references_cited_in(std::string_view text) {
  std::vector<Reference> out;
  for (std::size_t open = text.find('['); open != std::string_view::npos; open = text.find('[', open + 1)) {
    const std::size_t close = text.find(']', open);
    if (close == std::string_view::npos) break;
    const std::string_view key = text.substr(open + 1, close - open - 1);
    const auto& all = references();
    const auto it = std::find_if(all.begin(), all.end(), [&](const Reference& r) { return r.key == key; });
    if (it == all.end()) continue;
    if (std::none_of(out.begin(), out.end(), [&](const Reference& r) { return r.key == key; })) out.push_back(*it);
  }
  return out;
}

}  // namespace vrsph
