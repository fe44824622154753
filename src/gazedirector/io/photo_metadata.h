#pragma once

#include <filesystem>
#include <memory>

namespace gazedirector {

// What a photo carries besides its pixels and an edit of it keeps: EXIF (the
// camera, the time and place it was taken), IPTC and XMP (captions, rights)
// and the ICC profile of the colour space its values are in. Read and written
// with exiv2, in the formats it writes (JPEG, PNG, WebP, TIFF).
class PhotoMetadata {
 public:
  // Empty where the photo holds none or exiv2 cannot read it.
  static PhotoMetadata Read(const std::filesystem::path& photo);
  bool empty() const { return data_ == nullptr; }

  // Writes the metadata into `image_file`, a picture of it just written,
  // `width` x `height` and upright: the EXIF and XMP orientation become 1
  // (pixels are written upright), the pixel dimensions the file's, and the
  // EXIF thumbnail, which would show the unedited picture, is left out.
  // False, the file left as it was, where its format holds no metadata or
  // exiv2 cannot write it.
  bool WriteTo(const std::filesystem::path& image_file, int width, int height) const;

 private:
  struct Data;
  std::shared_ptr<const Data> data_;
};

}  // namespace gazedirector
