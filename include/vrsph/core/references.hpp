// SPDX-License-Identifier: BSD-3-Clause
#pragma once
// The publications vrsph implements and cites, as users cite them: authors, title, venue,
// year and an identifier (arXiv or DOI) where one was confirmed (docs/references.md says
// which details come from where). Method descriptions refer to them by key, "[QW] §4-5".
#include <string>
#include <string_view>
#include <vector>

namespace vrsph {

struct Reference {
  std::string_view key;         ///< "QW", "AAR", "SPE", "IM", ...
  std::string_view authors;     ///< "Z. Qiao, Y. Wei"
  std::string_view title;
  std::string_view venue;       ///< journal, volume and pages, or "preprint"
  int year = 0;
  std::string_view identifier;  ///< "arXiv:2503.15188", "doi:10.1007/...", or empty when none is known
  /// One line: authors, title, venue (year), identifier.
  std::string citation() const;
};

/// Every publication the code cites, the four implemented papers first.
const std::vector<Reference>& references();
/// The publications cited in `text` by their keys in brackets ("[QW] §4; [AAR](27)" -> QW,
/// AAR), in order of first appearance, each once. Unknown keys are skipped.
std::vector<Reference> references_cited_in(std::string_view text);

}  // namespace vrsph
