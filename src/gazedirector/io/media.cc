#include "gazedirector/io/media.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <fstream>
#include <vector>

#include "gazedirector/util/error.h"

namespace gazedirector {
namespace fs = std::filesystem;
namespace {

std::vector<uint8_t> ReadBytes(const fs::path& path, std::size_t offset, std::size_t count) {
  std::ifstream stream(path, std::ios::binary);
  stream.seekg(static_cast<std::streamoff>(offset));
  std::vector<uint8_t> bytes(count);
  stream.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(count));
  bytes.resize(static_cast<std::size_t>(std::max<std::streamsize>(stream.gcount(), 0)));
  return bytes;
}

bool StartsWith(const std::vector<uint8_t>& bytes, std::size_t offset, std::string_view text) {
  if (bytes.size() < offset + text.size()) return false;
  return std::equal(text.begin(), text.end(), bytes.begin() + static_cast<std::ptrdiff_t>(offset),
                    [](char a, uint8_t b) { return static_cast<uint8_t>(a) == b; });
}

bool IsImageExtension(const std::string& ext) {
  static const std::array<std::string_view, 10> kExt = {".jpg", ".jpeg", ".png", ".bmp", ".tif",
                                                         ".tiff", ".webp", ".pgm", ".ppm", ".pnm"};
  return std::find(kExt.begin(), kExt.end(), ext) != kExt.end();
}

uint32_t BigEndian32(const std::vector<uint8_t>& b, std::size_t i) {
  return (uint32_t{b[i]} << 24) | (uint32_t{b[i + 1]} << 16) | (uint32_t{b[i + 2]} << 8) | b[i + 3];
}

std::optional<ImageHeader> ProbePng(const fs::path& path, std::uintmax_t size) {
  const std::vector<uint8_t> head = ReadBytes(path, 0, 24);
  ImageHeader header{"png"};
  if (head.size() < 24 || !StartsWith(head, 12, "IHDR")) {
    header.complete = false;
    return header;
  }
  header.width = static_cast<int>(std::min<uint32_t>(BigEndian32(head, 16), 1u << 30));
  header.height = static_cast<int>(std::min<uint32_t>(BigEndian32(head, 20), 1u << 30));
  const std::size_t tail_size = static_cast<std::size_t>(std::min<std::uintmax_t>(size, 64));
  const std::vector<uint8_t> tail = ReadBytes(path, size - tail_size, tail_size);
  const std::string tail_text(tail.begin(), tail.end());
  header.complete = tail_text.find("IEND") != std::string::npos;
  return header;
}

std::optional<ImageHeader> ProbeJpeg(const fs::path& path, std::uintmax_t size) {
  ImageHeader header{"jpeg"};
  // Walk the marker segments up to the first start-of-frame.
  std::ifstream stream(path, std::ios::binary);
  stream.seekg(2);
  for (int guard = 0; guard < 10000 && stream.good(); ++guard) {
    int byte = stream.get();
    if (byte != 0xFF) continue;
    int marker = stream.get();
    while (marker == 0xFF) marker = stream.get();
    if (marker < 0 || marker == 0xD8 || marker == 0x01 || (marker >= 0xD0 && marker <= 0xD7)) continue;
    if (marker == 0xD9 || marker == 0xDA) break;
    const int hi = stream.get(), lo = stream.get();
    if (hi < 0 || lo < 0) break;
    const int length = (hi << 8) | lo;
    const bool is_sof = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
    if (is_sof) {
      std::array<uint8_t, 5> sof{};
      stream.read(reinterpret_cast<char*>(sof.data()), 5);
      header.height = (sof[1] << 8) | sof[2];
      header.width = (sof[3] << 8) | sof[4];
      break;
    }
    stream.seekg(length - 2, std::ios::cur);
  }
  // A complete JPEG ends with the EOI marker (a few padding bytes may follow).
  const std::size_t tail_size = static_cast<std::size_t>(std::min<std::uintmax_t>(size, 256));
  const std::vector<uint8_t> tail = ReadBytes(path, size - tail_size, tail_size);
  header.complete = false;
  for (std::size_t i = 0; i + 1 < tail.size(); ++i) {
    if (tail[i] == 0xFF && tail[i + 1] == 0xD9) header.complete = true;
  }
  return header;
}

}  // namespace

std::string LowerExtension(const fs::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return std::tolower(c); });
  return extension;
}

const std::vector<std::string>& VideoExtensions() {
  static const std::vector<std::string> extensions = {".mp4", ".mov", ".m4v", ".mkv", ".avi", ".webm", ".gif"};
  return extensions;
}

bool HasImageExtension(const fs::path& path) { return IsImageExtension(LowerExtension(path)); }

bool HasVideoExtension(const fs::path& path) {
  const std::vector<std::string>& extensions = VideoExtensions();
  return std::find(extensions.begin(), extensions.end(), LowerExtension(path)) != extensions.end();
}

MediaKind DetectMediaKind(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) Fail(ExitCode::kBadInput, "{}: no such file", path.string());
  if (!fs::is_regular_file(path, ec)) Fail(ExitCode::kBadInput, "{}: not a regular file", path.string());
  if (fs::file_size(path, ec) == 0) Fail(ExitCode::kBadInput, "{}: the file is empty", path.string());
  std::ifstream probe(path, std::ios::binary);
  if (!probe.good()) Fail(ExitCode::kBadInput, "{}: cannot open for reading", path.string());

  const std::vector<uint8_t> head = ReadBytes(path, 0, 16);
  const bool jpeg = head.size() >= 3 && head[0] == 0xFF && head[1] == 0xD8 && head[2] == 0xFF;
  const bool png = StartsWith(head, 0, "\x89PNG");
  const bool tiff = StartsWith(head, 0, std::string_view("II*\0", 4)) || StartsWith(head, 0, std::string_view("MM\0*", 4));
  const bool webp = StartsWith(head, 0, "RIFF") && StartsWith(head, 8, "WEBP");
  const bool bmp = StartsWith(head, 0, "BM");
  const bool pnm = head.size() >= 2 && head[0] == 'P' && head[1] >= '1' && head[1] <= '6';
  if (jpeg || png || tiff || webp || bmp || pnm) return MediaKind::kImage;

  const bool iso_media = StartsWith(head, 4, "ftyp");  // mp4, mov, m4v
  const bool avi = StartsWith(head, 0, "RIFF") && StartsWith(head, 8, "AVI ");
  const bool matroska = head.size() >= 4 && head[0] == 0x1A && head[1] == 0x45 && head[2] == 0xDF && head[3] == 0xA3;
  const bool gif = StartsWith(head, 0, "GIF8");
  if (iso_media || avi || matroska || gif) return MediaKind::kVideo;

  const std::string ext = LowerExtension(path);
  if (IsImageExtension(ext)) return MediaKind::kImage;
  if (HasVideoExtension(path)) return MediaKind::kVideo;
  Fail(ExitCode::kBadInput, "{}: not a recognised image or video file", path.string());
}

std::vector<fs::path> FilesIn(const fs::path& folder, bool recursive, const std::vector<fs::path>& skipped) {
  const auto hidden = [](const fs::path& path) { return path.filename().string().starts_with('.'); };
  const auto is_skipped = [&](const fs::path& path) {
    std::error_code ec;
    return std::any_of(skipped.begin(), skipped.end(), [&](const fs::path& other) { return fs::equivalent(path, other, ec); });
  };
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(folder, fs::directory_options::skip_permission_denied, ec), end;
       !ec && it != end; it.increment(ec)) {
    const fs::path& path = it->path();
    std::error_code kind_ec;
    if (it->is_directory(kind_ec)) {
      if (!recursive || hidden(path) || is_skipped(path)) it.disable_recursion_pending();
    } else if (!hidden(path) && it->is_regular_file(kind_ec)) {
      files.push_back(path);
    }
  }
  if (ec) Fail(ExitCode::kBadInput, "{}: cannot list the folder ({})", folder.string(), ec.message());
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<fs::path> MediaFilesIn(const fs::path& folder, bool recursive, const std::vector<fs::path>& skipped) {
  std::vector<fs::path> files = FilesIn(folder, recursive, skipped);
  std::erase_if(files, [](const fs::path& path) { return !HasImageExtension(path) && !HasVideoExtension(path); });
  return files;
}

std::optional<ImageHeader> ProbeImageHeader(const fs::path& path) {
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec || size < 8) return std::nullopt;
  const std::vector<uint8_t> head = ReadBytes(path, 0, 8);
  if (StartsWith(head, 0, "\x89PNG")) return ProbePng(path, size);
  if (head[0] == 0xFF && head[1] == 0xD8) return ProbeJpeg(path, size);
  return std::nullopt;
}

}  // namespace gazedirector
