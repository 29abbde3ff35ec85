// A whole file mapped read-only into memory, so readers parse it in place and
// point caches read one frame's bytes without loading the rest.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

namespace snag::io {

class MappedFile {
 public:
  /// Maps `path` read-only. An empty file maps to an empty view.
  /// Throws InputError when the file is missing, not a regular file or unreadable.
  explicit MappedFile(const std::string& path);
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  MappedFile(MappedFile&& other) noexcept;
  MappedFile& operator=(MappedFile&& other) noexcept;

  /// The file's bytes; valid while this object lives.
  std::string_view bytes() const { return {data_, size_}; }
  const std::string& path() const { return path_; }
  /// Says that bytes [offset, offset + length) will not be read again soon:
  /// the pages that hold them leave this process's resident memory (they stay
  /// in the page cache and are read back if touched again, so the mapping's
  /// contents never change), so that reading a long cache frame after frame
  /// keeps the resident size flat.
  void release(std::size_t offset, std::size_t length) const;

 private:
  std::string path_;
  const char* data_ = nullptr;
  std::size_t size_ = 0;
};

}  // namespace snag::io
