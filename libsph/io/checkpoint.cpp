#include "libsph/io/checkpoint.hpp"

#include <csignal>
#include <cstring>
#include <fstream>
#include <sstream>

#include "libsph/io/atomic_file.hpp"
#include "libsph/io/parameters.hpp"

namespace sph {
namespace {

constexpr std::string_view magic = "CARDIOSPH-CHECKPOINT\n";

volatile std::sig_atomic_t interrupt_flag = 0;

std::uint64_t fnv1a(std::string_view bytes) {
  std::uint64_t hash = 14695981039346656037ull;
  for (const char c : bytes) {
    hash ^= static_cast<unsigned char>(c);
    hash *= 1099511628211ull;
  }
  return hash;
}

template <class T>
void put(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(T));
}
void put_string(std::string& out, std::string_view s) {
  put<std::uint64_t>(out, s.size());
  out.append(s);
}

// Reads values from a byte range; every read is bounds-checked.
class Cursor {
 public:
  Cursor(std::string_view bytes, const std::string& source) : bytes_(bytes), source_(source) {}
  template <class T>
  T get(const char* what) {
    need(sizeof(T), what);
    T value;
    std::memcpy(&value, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return value;
  }
  std::string_view get_bytes(std::uint64_t n, const char* what) {
    need(n, what);
    const auto view = bytes_.substr(at_, n);
    at_ += n;
    return view;
  }
  std::string get_string(const char* what) { return std::string(get_bytes(get<std::uint64_t>(what), what)); }
  std::size_t remaining() const { return bytes_.size() - at_; }
  [[noreturn]] void fail(const std::string& problem) const {
    throw ParameterError("checkpoint '" + source_ + "' " + problem);
  }

 private:
  void need(std::uint64_t n, const char* what) const {
    if (n > remaining())
      fail("is damaged: " + std::string(what) + " needs " + std::to_string(n) + " bytes at byte " + std::to_string(at_) +
           ", only " + std::to_string(remaining()) + " are left");
  }
  std::string_view bytes_;
  const std::string& source_;
  std::size_t at_ = 0;
};

}  // namespace

std::string serialise_checkpoint(const Checkpoint& c) {
  std::string payload;
  put_string(payload, c.scene);
  put_string(payload, c.parameters);
  put<double>(payload, c.time);
  put<std::uint64_t>(payload, c.records.size());
  for (const auto& [key, bytes] : c.records) {
    put_string(payload, key);
    put_string(payload, bytes);
  }
  std::string out(magic);
  put<std::uint32_t>(out, checkpoint_format_version);
  put<std::uint64_t>(out, payload.size());
  out += payload;
  put<std::uint64_t>(out, fnv1a(payload));
  return out;
}

Checkpoint parse_checkpoint(std::string_view bytes, const std::string& source) {
  Cursor head(bytes, source);
  if (bytes.size() < magic.size() || bytes.substr(0, magic.size()) != magic)
    head.fail("is not a cardiosph checkpoint (it does not start with " + std::string(magic.substr(0, magic.size() - 1)) + ")");
  head.get_bytes(magic.size(), "the magic");
  const auto version = head.get<std::uint32_t>("the format version");
  if (version != checkpoint_format_version)
    head.fail("has format version " + std::to_string(version) + "; this build reads version " +
              std::to_string(checkpoint_format_version));
  const auto length = head.get<std::uint64_t>("the payload length");
  if (length > head.remaining() || head.remaining() - length < sizeof(std::uint64_t))
    head.fail("is truncated: " + std::to_string(bytes.size()) + " bytes, the header announces " +
              std::to_string(magic.size() + 12 + length + 8));
  const auto payload = head.get_bytes(length, "the payload");
  const auto hash = head.get<std::uint64_t>("the hash");
  if (head.remaining() != 0) head.fail("has " + std::to_string(head.remaining()) + " bytes after its end");
  if (hash != fnv1a(payload)) head.fail("is damaged: its hash does not match its contents");

  Cursor in(payload, source);
  Checkpoint c;
  c.scene = in.get_string("the scene");
  c.parameters = in.get_string("the parameters");
  c.time = in.get<double>("the time");
  const auto n = in.get<std::uint64_t>("the record count");
  for (std::uint64_t k = 0; k < n; ++k) {
    std::string key = in.get_string("a record key");
    std::string value = in.get_string("a record");
    if (!c.records.emplace(std::move(key), std::move(value)).second) in.fail("is damaged: a record key appears twice");
  }
  if (in.remaining() != 0) in.fail("is damaged: bytes after the last record");
  return c;
}

Checkpoint read_checkpoint(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw ParameterError("checkpoint '" + path.string() + "' does not exist (a run writes it when interrupted or with --checkpoint-interval)");
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  if (!in) throw ParameterError("checkpoint '" + path.string() + "' cannot be read");
  return parse_checkpoint(s.str(), path.string());
}

void write_checkpoint(const std::filesystem::path& path, const Checkpoint& checkpoint) {
  write_file_atomically(path, serialise_checkpoint(checkpoint));
}

RunInterrupted::RunInterrupted(double time, std::filesystem::path checkpoint)
    : std::runtime_error("interrupted at simulated time " + std::to_string(time) + "; state saved in " + checkpoint.string()),
      time_(time),
      checkpoint_(std::move(checkpoint)) {}

void request_interrupt() noexcept { interrupt_flag = 1; }
bool interrupt_requested() noexcept { return interrupt_flag != 0; }
void clear_interrupt() noexcept { interrupt_flag = 0; }

std::string checkpoint_file_of_rank(int rank) {
  return rank == 0 ? std::string(checkpoint_file_name) : "checkpoint.rank" + std::to_string(rank) + ".bin";
}

int checkpoint_ranks(const std::filesystem::path& folder) {
  int ranks = 1;
  std::error_code error;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("checkpoint.rank", 0) == 0 && entry.path().extension() == ".bin") ++ranks;
  }
  return ranks;
}

}  // namespace sph
