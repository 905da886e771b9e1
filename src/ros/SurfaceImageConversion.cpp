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
  const std::size_t bytes = static_cast<std::size_t>(out.width) * out.height * 4;
  if (out.rgba.empty() || out.rgba.size() != bytes) return false;
  image.header = header;
  image.width = static_cast<std::uint32_t>(out.width);
  image.height = static_cast<std::uint32_t>(out.height);
  image.encoding = sensor_msgs::image_encodings::RGBA8;
  image.is_bigendian = 0;
  image.step = static_cast<std::uint32_t>(out.width) * 4;
  image.data.assign(out.rgba.begin(), out.rgba.end());
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
