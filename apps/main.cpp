// cardiosph: one executable, one subcommand per scene. See README.md and `cardiosph --help`.
#include "apps/cli.hpp"

int main(int argc, char** argv) { return cardiosph::run_cli(argc, argv); }
