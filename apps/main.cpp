// cardiosph: one executable, one subcommand per scene. See README.md and `cardiosph --help`.
#include <iostream>

#include "apps/cli.hpp"
#include "libsph/core/communicator.hpp"

int main(int argc, char** argv) {
  // Under mpirun every rank runs the same command; rank 0 alone prints (and writes files).
  const sph::MpiSession mpi(argc, argv);
  if (!sph::Communicator::world().is_root()) {
    std::cout.setstate(std::ios::failbit);
    std::cerr.setstate(std::ios::failbit);
  }
  return cardiosph::run_cli(argc, argv);
}
