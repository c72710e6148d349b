#include "sim/setup/png_writer.h"

#include <stb_image_write.h>

namespace lap::sim {

Status save_png(const haptics::RgbImage& image, const std::filesystem::path& file) {
  if (image.width <= 0 || image.height <= 0 ||
      image.rgb.size() != static_cast<size_t>(image.width) * image.height * 3) {
    return file_diagnostic(file.string(), 0, "", "image size and pixel data do not agree");
  }
  if (stbi_write_png(file.string().c_str(), image.width, image.height, 3, image.rgb.data(),
                     image.width * 3) == 0) {
    return file_diagnostic(file.string(), 0, "", "cannot write the PNG file");
  }
  return {};
}

Status save_grey_png(int width, int height, const std::vector<uint8_t>& grey,
                     const std::filesystem::path& file) {
  if (width <= 0 || height <= 0 || grey.size() != static_cast<size_t>(width) * height) {
    return file_diagnostic(file.string(), 0, "", "image size and pixel data do not agree");
  }
  if (stbi_write_png(file.string().c_str(), width, height, 1, grey.data(), width) == 0) {
    return file_diagnostic(file.string(), 0, "", "cannot write the PNG file");
  }
  return {};
}

}  // namespace lap::sim
