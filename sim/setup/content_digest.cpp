#include "sim/setup/content_digest.h"

#include "core/bounded_file.h"

namespace lap::sim {

uint64_t content_digest(std::string_view bytes) {
  uint64_t h = 1469598103934665603ULL;  // FNV-1a 64's offset basis and prime
  for (const char c : bytes) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ULL;
  return h;
}

Result<uint64_t> file_digest(const std::filesystem::path& file, std::uintmax_t max_bytes) {
  const Result<std::string> bytes = read_bounded_file(file, max_bytes, "a scenario file");
  if (!bytes.ok()) return bytes.diagnostics();
  return content_digest(bytes.value());
}

}  // namespace lap::sim
