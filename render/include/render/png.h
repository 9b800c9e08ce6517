// PNG files of rendered images (libpng): 8-bit RGB colour and 16-bit grey (e.g. a depth image in
// millimetres). Rows may be given bottom-up, as OpenGL reads them (render/offscreen.h), and are
// then written top-down. Every libpng and stdio error is seen: a file not written whole is a
// failure with the file named.
#pragma once

#include <cstdint>
#include <string>

namespace ohrp::render {

// `rgb`: w x h x 3 bytes, rows top-down, or bottom-up when `bottom_up`.
bool WritePngRgb(const std::string& path, const uint8_t* rgb, int w, int h, bool bottom_up,
                 std::string* error);

// `grey`: w x h values, rows as above.
bool WritePngGrey16(const std::string& path, const uint16_t* grey, int w, int h, bool bottom_up,
                    std::string* error);

}  // namespace ohrp::render
