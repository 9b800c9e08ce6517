// PNG files of rendered images (see png.h).
#include "render/png.h"

#include <png.h>

#include <cstdio>
#include <vector>

namespace ohrp::render {
namespace {

// one image: `row(y)` gives the bytes of output row y (top-down)
template <typename Row>
bool Write(const std::string& path, int w, int h, int bit_depth, int colour, Row row,
           std::string* error) {
  FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) {
    *error = "cannot write '" + path + "'";
    return false;
  }
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  if (!png || !info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    std::fclose(f);
    *error = "libpng failed on '" + path + "' (disk full?)";
    return false;
  }
  png_init_io(png, f);
  png_set_IHDR(png, info, w, h, bit_depth, colour, PNG_INTERLACE_NONE,
               PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  if (bit_depth == 16) png_set_swap(png);  // PNG is big-endian; the machine's uint16_t is not
  for (int y = 0; y < h; ++y) png_write_row(png, row(y));
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  const bool flushed = std::fflush(f) == 0 && !std::ferror(f);
  if (std::fclose(f) != 0 || !flushed) {
    *error = "'" + path + "' was not written whole (disk full?)";
    return false;
  }
  return true;
}

}  // namespace

bool WritePngRgb(const std::string& path, const uint8_t* rgb, int w, int h, bool bottom_up,
                 std::string* error) {
  return Write(path, w, h, 8, PNG_COLOR_TYPE_RGB, [&](int y) {
    const int src = bottom_up ? h - 1 - y : y;
    return const_cast<png_bytep>(rgb + static_cast<size_t>(src) * w * 3);
  }, error);
}

bool WritePngGrey16(const std::string& path, const uint16_t* grey, int w, int h, bool bottom_up,
                    std::string* error) {
  return Write(path, w, h, 16, PNG_COLOR_TYPE_GRAY, [&](int y) {
    const int src = bottom_up ? h - 1 - y : y;
    return reinterpret_cast<png_bytep>(const_cast<uint16_t*>(grey + static_cast<size_t>(src) * w));
  }, error);
}

}  // namespace ohrp::render
