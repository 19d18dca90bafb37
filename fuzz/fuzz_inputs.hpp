#pragma once
// What the fuzz targets feed the readers, shared by the libFuzzer binaries (fuzz_<target>.cpp,
// built with clang, CARDIOSPH_FUZZ=ON) and the test that replays the corpus in the default suite
// (tests/test_fuzz_corpus.cpp). Each function takes arbitrary bytes and returns normally when the
// reader accepted them or rejected them with its documented error (MeshError, ParameterError,
// StateError: a clear message). Anything else escapes: a crash, a sanitizer report, or another
// exception (std::bad_alloc from a count the file cannot hold, std::out_of_range, ...) is a bug.

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace cardiosph::fuzz {

using Bytes = std::span<const std::uint8_t>;

/// Surface meshes: the first byte chooses STL, OBJ or PLY; the rest is the file, read and checked.
void surface_mesh(Bytes data);
/// Tetrahedral meshes: the first byte chooses a .vtu or an openCARP mesh; for openCARP the rest is
/// split at lines "%%" into the .pts, .elem, .lon and .vtx files. Read, checked, and its boundary taken.
void tet_mesh(Bytes data);
/// Config files: the first byte chooses TOML or JSON; the rest is the text, applied to parameters
/// of every kind (numbers with ranges, integers, booleans, choices, vectors, paths, text).
void config(Bytes data);
/// The --set parser: every line is an assignment key=value applied to the same parameters.
void assignments(Bytes data);
/// Checkpoints: the bytes are parsed as a checkpoint file and, if accepted, loaded into a particle
/// set and a time stepper.
void checkpoint(Bytes data);

struct Target {
  const char* name;
  void (*run)(Bytes);
};
/// Every target, by the name of its corpus folder (fuzz/corpus/<name>).
const std::vector<Target>& targets();

}  // namespace cardiosph::fuzz
