// cardiosph: one executable, one subcommand per scene. See README.md and `cardiosph --help`.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <thread>

#include "apps/cli.hpp"
#include "libsph/core/communicator.hpp"

int main(int argc, char** argv) {
  // Under mpirun every rank runs the same command; rank 0 alone prints (and writes files).
  const sph::MpiSession mpi(argc, argv);
  const sph::Communicator& world = sph::Communicator::world();
  std::ostringstream rank_errors;
  std::streambuf* const standard_error = std::cerr.rdbuf();
  if (!world.is_root()) {
    std::cout.setstate(std::ios::failbit);
    std::cerr.rdbuf(rank_errors.rdbuf());
  }
  const int code = cardiosph::run_cli(argc, argv);
  std::cerr.rdbuf(standard_error);
  // (an interruption is collective: every rank stops after the same step, with code 3)
  if (world.size() > 1 && code != 0 && code != 3) {
    // An error that only some ranks met (a parameter they read differently, a file one node lacks)
    // would leave the others waiting in a collective: every failing rank ends the run. Rank 0 does
    // so at once with its message printed; another rank waits a moment first, so that an error
    // every rank met is reported once, by rank 0, and prints its own message only if it is alone.
    if (!world.is_root()) {
      std::this_thread::sleep_for(std::chrono::seconds(1));
      std::fprintf(stderr, "(rank %d) %s", world.rank(), rank_errors.str().c_str());
      std::fflush(stderr);
    }
    world.abort(code);
  }
  return code;
}
