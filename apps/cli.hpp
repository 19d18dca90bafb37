#pragma once
// The `cardiosph` command line: `cardiosph list`, `cardiosph SCENE [options]`,
// `cardiosph study SCENE --sweep key=a,b,c [options]`.
// Exit codes: 0 success, 1 the run failed (numerical failure or I/O error), 2 bad input.

namespace cardiosph {

int run_cli(int argc, const char* const* argv);

}  // namespace cardiosph
