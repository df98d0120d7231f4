// vrsph command-line tool. The only place in vrsph that prints errors and decides
// exit codes:
//   0 success · 1 command-line usage (CLI11) · 2 ConfigError (unknown method/option/...)
//   3 InputError (bad data) · 4 GeometryError · 5 NumericalError · 70 internal error
#include <iostream>
#include <vrsph/core/error.hpp>
#include "commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"vrsph — particle discretisations of elliptic operators on irregular point clouds"};
  app.set_version_flag("--version", std::string("vrsph ") + VRSPH_VERSION);
  app.require_subcommand(1);
  vrsph::cli::add_methods_command(app);
  vrsph::cli::add_kernels_command(app);
  vrsph::cli::add_cloud_command(app);
  vrsph::cli::add_operator_command(app);
  vrsph::cli::add_study_command(app);
  vrsph::cli::add_solve_command(app);
  vrsph::cli::add_spectrum_command(app);
  vrsph::cli::add_bench_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 1;
  } catch (const vrsph::ConfigError& e) {
    std::cerr << "vrsph: configuration error: " << e.what() << '\n';
    return 2;
  } catch (const vrsph::InputError& e) {
    std::cerr << "vrsph: input error: " << e.what() << '\n';
    return 3;
  } catch (const vrsph::GeometryError& e) {
    std::cerr << "vrsph: geometry error: " << e.what() << '\n';
    return 4;
  } catch (const vrsph::NumericalError& e) {
    std::cerr << "vrsph: numerical error: " << e.what() << '\n';
    return 5;
  } catch (const std::exception& e) {
    std::cerr << "vrsph: internal error: " << e.what() << '\n';
    return 70;
  }
  return 0;
}
