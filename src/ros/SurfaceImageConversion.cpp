#include "pbf_ros/ros/SurfaceImageConversion.h"

#include <cstring>
#include <sensor_msgs/image_encodings.h>

namespace pbf_ros {

namespace {
bool littleEndian() {
  const std::uint16_t one = 1;
  return *reinterpret_cast<const std::uint8_t*>(&one) == 1;
}
}  // namespace

bool toColorImage(const pbf::RenderOutput& out, const std_msgs::Header& header,
                  sensor_msgs::Image& image) {
  const std::size_t pixels = static_cast<std::size_t>(out.width) * out.height;
  if (out.rgba.empty() || out.rgba.size() != pixels * 4) return false;
  image.header = header;
  image.width = static_cast<std::uint32_t>(out.width);
  image.height = static_cast<std::uint32_t>(out.height);
  // rgb8: the fluid and the floor are opaque; only render_background:=false leaves alpha
  // 0 behind the fluid, and the depth image (NaN there) already marks those pixels. rgb8
  // is what image_view, rviz and depth_image_proc's point_cloud_xyzrgb take as is, and a
  // quarter smaller on the wire.
  image.encoding = sensor_msgs::image_encodings::RGB8;
  image.is_bigendian = 0;
  image.step = static_cast<std::uint32_t>(out.width) * 3;
  image.data.resize(pixels * 3);
  const std::uint8_t* src = out.rgba.data();
  std::uint8_t* dst = image.data.data();
  for (std::size_t i = 0; i < pixels; ++i, src += 4, dst += 3) {
    dst[0] = src[0];
    dst[1] = src[1];
    dst[2] = src[2];
  }
  return true;
}

bool toDepthImage(const pbf::RenderOutput& out, const std_msgs::Header& header,
                  sensor_msgs::Image& image) {
  const std::size_t pixels = static_cast<std::size_t>(out.width) * out.height;
  if (out.depth.empty() || out.depth.size() != pixels) return false;
  image.header = header;
  image.width = static_cast<std::uint32_t>(out.width);
  image.height = static_cast<std::uint32_t>(out.height);
  image.encoding = sensor_msgs::image_encodings::TYPE_32FC1;
  image.is_bigendian = littleEndian() ? 0 : 1;
  image.step = static_cast<std::uint32_t>(out.width) * sizeof(float);
  image.data.resize(pixels * sizeof(float));
  std::memcpy(image.data.data(), out.depth.data(), image.data.size());
  return true;
}

}  // namespace pbf_ros
