#pragma once
// Reads the 8-bit RGB or RGBA, non-interlaced PNG files that Chromium's --screenshot writes,
// enough for a test to look at the pixels (zlib inflates; the five row filters are undone here).
#include <zlib.h>

#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace fnopt::testing {

struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;  // 3 bytes per pixel, rows top to bottom
  const std::uint8_t* pixel(int x, int y) const { return &rgb[3 * (static_cast<std::size_t>(y) * width + x)]; }
};

// An empty image (width 0) if the file is not a PNG of that kind.
inline RgbImage read_png(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  auto u32 = [&](std::size_t at) {
    return static_cast<std::uint32_t>(static_cast<std::uint8_t>(data[at])) << 24 |
           static_cast<std::uint32_t>(static_cast<std::uint8_t>(data[at + 1])) << 16 |
           static_cast<std::uint32_t>(static_cast<std::uint8_t>(data[at + 2])) << 8 |
           static_cast<std::uint8_t>(data[at + 3]);
  };
  RgbImage image;
  if (data.size() < 33 || data.compare(1, 3, "PNG") != 0) return image;
  int channels = 0;
  std::string compressed;
  for (std::size_t at = 8; at + 12 <= data.size();) {
    const std::uint32_t length = u32(at);
    const std::string type = data.substr(at + 4, 4);
    if (at + 12 + length > data.size()) return {};
    if (type == "IHDR") {
      image.width = static_cast<int>(u32(at + 8));
      image.height = static_cast<int>(u32(at + 12));
      const int depth = data[at + 16], colour = data[at + 17], interlace = data[at + 20];
      channels = colour == 2 ? 3 : colour == 6 ? 4 : 0;
      if (depth != 8 || channels == 0 || interlace != 0) return {};
    } else if (type == "IDAT") {
      compressed += data.substr(at + 8, length);
    }
    at += 12 + length;
  }
  const std::size_t stride = static_cast<std::size_t>(image.width) * channels;
  std::vector<std::uint8_t> raw((stride + 1) * image.height);
  uLongf raw_size = raw.size();
  if (uncompress(raw.data(), &raw_size, reinterpret_cast<const Bytef*>(compressed.data()), compressed.size()) != Z_OK ||
      raw_size != raw.size())
    return {};
  std::vector<std::uint8_t> previous(stride, 0), row(stride);
  image.rgb.resize(3 * static_cast<std::size_t>(image.width) * image.height);
  for (int y = 0; y < image.height; ++y) {
    const std::uint8_t filter = raw[y * (stride + 1)];
    const std::uint8_t* line = &raw[y * (stride + 1) + 1];
    for (std::size_t k = 0; k < stride; ++k) {
      const int a = k >= static_cast<std::size_t>(channels) ? row[k - channels] : 0, b = previous[k],
                c = k >= static_cast<std::size_t>(channels) ? previous[k - channels] : 0;
      int predicted = 0;
      if (filter == 1) predicted = a;
      if (filter == 2) predicted = b;
      if (filter == 3) predicted = (a + b) / 2;
      if (filter == 4) {
        const int p = a + b - c, pa = std::abs(p - a), pb = std::abs(p - b), pc = std::abs(p - c);
        predicted = pa <= pb && pa <= pc ? a : pb <= pc ? b : c;
      }
      row[k] = static_cast<std::uint8_t>(line[k] + predicted);
    }
    for (int x = 0; x < image.width; ++x)
      for (int c = 0; c < 3; ++c)
        image.rgb[3 * (static_cast<std::size_t>(y) * image.width + x) + c] = row[x * channels + c];
    previous = row;
  }
  return image;
}

}  // namespace fnopt::testing
