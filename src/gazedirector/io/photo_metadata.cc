#include "gazedirector/io/photo_metadata.h"

#include <exiv2/exiv2.hpp>

namespace gazedirector {

struct PhotoMetadata::Data {
  Exiv2::ExifData exif;
  Exiv2::IptcData iptc;
  Exiv2::XmpData xmp;
  Exiv2::DataBuf icc;
};

namespace {

// exiv2 reports odd metadata on stderr; a photo's oddities are not the user's concern here.
void SilenceExiv2() { Exiv2::LogMsg::setLevel(Exiv2::LogMsg::mute); }

// Sets `key` to `value` where the metadata holds it.
template <typename Metadata, typename Key, typename Value>
void SetWhereHeld(Metadata& metadata, const Key& key, const Value& value) {
  const auto found = metadata.findKey(key);
  if (found != metadata.end()) *found = value;
}

}  // namespace

PhotoMetadata PhotoMetadata::Read(const std::filesystem::path& photo) {
  SilenceExiv2();
  PhotoMetadata metadata;
  try {
    const Exiv2::Image::AutoPtr image = Exiv2::ImageFactory::open(photo.string());
    image->readMetadata();
    auto data = std::make_shared<Data>();
    data->exif = image->exifData();
    data->iptc = image->iptcData();
    data->xmp = image->xmpData();
    if (image->iccProfileDefined()) data->icc = Exiv2::DataBuf(image->iccProfile()->pData_, image->iccProfile()->size_);
    if (!data->exif.empty() || !data->iptc.empty() || !data->xmp.empty() || data->icc.size_ > 0) {
      metadata.data_ = std::move(data);
    }
  } catch (const Exiv2::AnyError&) {
    // Unreadable metadata: the photo is still a photo.
  }
  return metadata;
}

bool PhotoMetadata::WriteTo(const std::filesystem::path& image_file, int width, int height) const {
  if (empty()) return true;
  SilenceExiv2();
  try {
    const Exiv2::Image::AutoPtr image = Exiv2::ImageFactory::open(image_file.string());
    image->readMetadata();
    Exiv2::ExifData exif = data_->exif;
    Exiv2::ExifThumb(exif).erase();
    SetWhereHeld(exif, Exiv2::ExifKey("Exif.Image.Orientation"), uint16_t{1});
    SetWhereHeld(exif, Exiv2::ExifKey("Exif.Photo.PixelXDimension"), uint32_t(width));
    SetWhereHeld(exif, Exiv2::ExifKey("Exif.Photo.PixelYDimension"), uint32_t(height));
    Exiv2::XmpData xmp = data_->xmp;
    SetWhereHeld(xmp, Exiv2::XmpKey("Xmp.tiff.Orientation"), uint16_t{1});
    image->setExifData(exif);
    image->setIptcData(data_->iptc);
    image->setXmpData(xmp);
    if (data_->icc.size_ > 0) {
      Exiv2::DataBuf icc(data_->icc.pData_, data_->icc.size_);
      image->setIccProfile(icc, false);
    }
    image->writeMetadata();
    return true;
  } catch (const Exiv2::AnyError&) {
    return false;
  }
}

}  // namespace gazedirector
