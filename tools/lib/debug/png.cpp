// PNG encoding of pictures with stb_image_write (Debian's libstb-dev). The
// one STB_IMAGE_WRITE_IMPLEMENTATION of the library lives here.
#define STB_IMAGE_WRITE_IMPLEMENTATION
#define STBI_WRITE_NO_STDIO
#include <stb/stb_image_write.h>

#include <fstream>

#include "cmkit/tools/picture.h"

namespace cmkit {
namespace {

/// Bytes per pixel of an Image.
constexpr int kChannels = 4;

void appendBytes(void* context, void* data, int size) {
  auto* out = static_cast<std::vector<std::uint8_t>*>(context);
  const auto* bytes = static_cast<const std::uint8_t*>(data);
  out->insert(out->end(), bytes, bytes + size);
}

}  // namespace

Result<std::vector<std::uint8_t>> encodePng(const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgba.size() != std::size_t(image.width) * std::size_t(image.height) * kChannels)
    return Error{"picture has no pixels or the wrong number of them"};
  std::vector<std::uint8_t> out;
  const int ok = stbi_write_png_to_func(appendBytes, &out, image.width, image.height, kChannels,
                                        image.rgba.data(), image.width * kChannels);
  if (ok == 0) return Error{"PNG encoding failed"};
  return out;
}

Status savePng(const std::string& path, const Image& image) {
  auto png = encodePng(image);
  if (!png) return png.error();
  std::ofstream out(path, std::ios::binary);
  if (!out) return Error{"cannot write the picture", path};
  out.write(reinterpret_cast<const char*>(png->data()), std::streamsize(png->size()));
  if (!out) return Error{"cannot write the picture", path};
  return Ok{};
}

}  // namespace cmkit
