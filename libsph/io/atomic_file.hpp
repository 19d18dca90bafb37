#pragma once
// Files are written under a temporary name in the same folder and then renamed over the target,
// so an interrupted run never leaves a truncated file behind.

#include <filesystem>
#include <string_view>

namespace sph {

/// Writes `content` to `path` atomically; throws std::runtime_error naming the path on failure.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

/// Temporary name used while writing `path` (same folder, so that the rename is atomic).
std::filesystem::path temporary_path_for(const std::filesystem::path& path);

/// Renames `temporary` over `path`; throws std::runtime_error naming both on failure.
void commit_temporary(const std::filesystem::path& temporary, const std::filesystem::path& path);

}  // namespace sph
