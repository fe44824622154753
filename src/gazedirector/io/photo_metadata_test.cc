#include "gazedirector/io/photo_metadata.h"

#include <string>
#include <vector>

#include <exiv2/exiv2.hpp>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "tests/test_data.h"

namespace gazedirector {
namespace {

namespace fs = std::filesystem;
using testing::DataPath;
using testing::ScratchDir;

Exiv2::Image::AutoPtr OpenWithMetadata(const fs::path& path) {
  Exiv2::Image::AutoPtr image = Exiv2::ImageFactory::open(path.string());
  image->readMetadata();
  return image;
}

std::string ExifValue(const fs::path& path, const std::string& key) {
  const Exiv2::Image::AutoPtr image = OpenWithMetadata(path);
  const auto found = image->exifData().findKey(Exiv2::ExifKey(key));
  return found == image->exifData().end() ? std::string("absent") : found->toString();
}

std::vector<unsigned char> IccProfile(const fs::path& path) {
  const Exiv2::Image::AutoPtr image = OpenWithMetadata(path);
  const Exiv2::DataBuf* icc = image->iccProfile();
  return {icc->pData_, icc->pData_ + icc->size_};
}

// A picture of `width` x `height` written as OpenCV writes the outputs: no metadata.
fs::path Picture(const fs::path& path, int width, int height) {
  cv::imwrite(path.string(), cv::Mat(height, width, CV_8UC3, cv::Scalar(40, 90, 160)));
  return path;
}

// d30.jpg's EXIF comes along into a new JPEG, told that the picture is now
// upright and as large as the file; a file without metadata reads empty.
TEST(PhotoMetadataTest, ExifComesAlongUprightAndAsLargeAsTheNewPicture) {
  const fs::path dir = ScratchDir("photo_metadata");
  // d30.jpg said "turn me a quarter" (EXIF orientation 6), as a phone's photo does.
  fs::copy_file(DataPath("images/d30.jpg"), dir / "turned.jpg", fs::copy_options::overwrite_existing);
  {
    const Exiv2::Image::AutoPtr image = OpenWithMetadata(dir / "turned.jpg");
    image->exifData()["Exif.Image.Orientation"] = uint16_t{6};
    image->writeMetadata();
  }
  const PhotoMetadata metadata = PhotoMetadata::Read(dir / "turned.jpg");
  ASSERT_FALSE(metadata.empty());
  const fs::path out = Picture(dir / "out.jpg", 900, 600);
  ASSERT_TRUE(ExifValue(out, "Exif.Photo.ColorSpace") == "absent");
  ASSERT_TRUE(metadata.WriteTo(out, 900, 600));
  EXPECT_EQ(ExifValue(out, "Exif.Image.Orientation"), "1");
  EXPECT_EQ(ExifValue(out, "Exif.Photo.PixelXDimension"), "900");
  EXPECT_EQ(ExifValue(out, "Exif.Photo.PixelYDimension"), "600");
  EXPECT_EQ(ExifValue(out, "Exif.Photo.ColorSpace"), ExifValue(DataPath("images/d30.jpg"), "Exif.Photo.ColorSpace"));
  EXPECT_EQ(cv::imread(out.string()).size(), cv::Size(900, 600));  // the pixels as written
  EXPECT_TRUE(PhotoMetadata::Read(DataPath("images/s12.jpg")).empty());
}

// A colour profile is carried byte for byte (JPEG into PNG), and a format
// that holds none (BMP) is left as it was.
TEST(PhotoMetadataTest, TheColourProfileComesAlongWhereTheFormatHoldsOne) {
  const fs::path dir = ScratchDir("photo_metadata_icc");
  const fs::path source = DataPath("dlib-faces/Tom_Cruise_avp_2014_4.jpg");
  const std::vector<unsigned char> profile = IccProfile(source);
  ASSERT_GT(profile.size(), 100u);
  const PhotoMetadata metadata = PhotoMetadata::Read(source);
  const fs::path png = Picture(dir / "out.png", 64, 48);
  ASSERT_TRUE(metadata.WriteTo(png, 64, 48));
  EXPECT_EQ(IccProfile(png), profile);
  const fs::path bmp = Picture(dir / "out.bmp", 64, 48);
  const auto size = fs::file_size(bmp);
  EXPECT_FALSE(metadata.WriteTo(bmp, 64, 48));
  EXPECT_EQ(fs::file_size(bmp), size);
}

}  // namespace
}  // namespace gazedirector
