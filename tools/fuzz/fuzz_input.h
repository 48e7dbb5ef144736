// Helpers shared by the fuzz targets: split one fuzzer input into named parts, and write files
// into a scratch directory (the readers under test take paths, as the services do).
#pragma once

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

namespace fleetloc::fuzz {

// The input cut at each "\n--\n" into at most `n` parts (missing parts are empty).
inline std::vector<std::string> SplitParts(const std::uint8_t* data, std::size_t size,
                                           std::size_t n) {
  std::vector<std::string> parts;
  std::string_view rest(reinterpret_cast<const char*>(data), size);
  while (parts.size() + 1 < n) {
    const std::size_t cut = rest.find("\n--\n");
    if (cut == std::string_view::npos) break;
    parts.emplace_back(rest.substr(0, cut));
    rest.remove_prefix(cut + 4);
  }
  parts.emplace_back(rest);
  parts.resize(n);
  return parts;
}

// A directory of this process under /dev/shm (or the temp dir), emptied for each input.
inline std::filesystem::path ScratchDir() {
  static const std::filesystem::path dir = [] {
    std::filesystem::path base =
        std::filesystem::exists("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path();
    return base / ("fleetloc_fuzz_" + std::to_string(::getpid()));
  }();
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  std::filesystem::create_directories(dir, ec);
  return dir;
}

inline void WriteFile(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

}  // namespace fleetloc::fuzz
