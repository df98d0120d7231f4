// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer harness: problem files (TOML) applied to a command with options of every kind
// the real commands have (text, integer, real, list, flag, path). toml++ parses, then every
// key is matched, converted and checked. Only vrsph::Error may escape; anything else (a
// crash, a sanitizer report, another exception such as CLI11's, a hang) is a finding.
#include <unistd.h>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>
#include <vrsph/core/error.hpp>
#include "problem_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = (std::filesystem::temp_directory_path() / ("vrsph_fuzz_problem_" + std::to_string(::getpid()) + ".toml")).string();
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  CLI::App app("fuzz");
  std::string method, u, cloud_file, config;
  int n = 0;
  double h = 0;
  std::vector<int> sizes;
  std::vector<std::string> methods;
  bool flag = false;
  app.add_option("--method", methods)->delimiter(',');
  app.add_option("--u", u);
  app.add_option("--cloud-file", cloud_file);
  app.add_option("--seed", n)->check(CLI::NonNegativeNumber);
  app.add_option("--h", h);
  app.add_option("--n", sizes)->delimiter(',');
  app.add_flag("--regular-layer", flag);
  vrsph::cli::add_config_option(&app, config);
  try {
    app.parse(std::vector<std::string>{});
    vrsph::cli::apply_problem_file(app, path);
  } catch (const vrsph::Error&) {
  }
  std::filesystem::remove(path);
  return 0;
}
