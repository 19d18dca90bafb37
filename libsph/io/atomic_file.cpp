#include "libsph/io/atomic_file.hpp"

#include <fstream>
#include <stdexcept>
#include <system_error>

namespace sph {

std::filesystem::path temporary_path_for(const std::filesystem::path& path) {
  auto temporary = path;
  temporary += ".partial";
  return temporary;
}

void commit_temporary(const std::filesystem::path& temporary, const std::filesystem::path& path) {
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error)
    throw std::runtime_error("cannot rename '" + temporary.string() + "' to '" + path.string() + "': " + error.message());
}

void write_file_atomically(const std::filesystem::path& path, std::string_view content) {
  const auto temporary = temporary_path_for(path);
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) throw std::runtime_error("cannot open '" + temporary.string() + "' for writing");
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) throw std::runtime_error("cannot write '" + temporary.string() + "'");
  }
  commit_temporary(temporary, path);
}

}  // namespace sph
