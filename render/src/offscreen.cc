// Offscreen rendering on OSMesa (offscreen.h).
#include "render/offscreen.h"

#include <GL/osmesa.h>

#include <algorithm>
#include <cstring>

namespace ohrp::render {

std::unique_ptr<Offscreen> Offscreen::Create(mjModel* m, const OffscreenOptions& options,
                                             std::string* error) {
  if (options.width <= 0 || options.height <= 0) {
    *error = "offscreen size " + std::to_string(options.width) + "x" +
             std::to_string(options.height) + " must be positive";
    return nullptr;
  }
  std::unique_ptr<Offscreen> r(new Offscreen());
  r->options_ = options;
  const std::size_t pixels = static_cast<std::size_t>(options.width) * options.height;
  r->gl_buffer_.resize(pixels * 4);
  r->rgb_.resize(pixels * 3);
  r->depth_.resize(pixels);
  // the OSMesa context first (RGBA, 24-bit depth, 8-bit stencil), then MuJoCo's
  OSMesaContext gl = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, nullptr);
  r->gl_ = gl;
  if (gl == nullptr || !OSMesaMakeCurrent(gl, r->gl_buffer_.data(), GL_UNSIGNED_BYTE,
                                          options.width, options.height)) {
    *error = "cannot create the OSMesa context (Debian's libosmesa6)";
    return nullptr;
  }
  m->vis.global.offwidth = std::max(m->vis.global.offwidth, options.width);
  m->vis.global.offheight = std::max(m->vis.global.offheight, options.height);
  if (options.samples >= 0) m->vis.quality.offsamples = options.samples;
  mjv_defaultScene(&r->scn_);
  mjv_defaultOption(&r->opt_);
  mjr_defaultContext(&r->con_);
  mjv_makeScene(m, &r->scn_, options.max_geoms);
  r->scene_made_ = true;
  mjr_makeContext(m, &r->con_, mjFONTSCALE_100);
  r->context_made_ = true;
  mjr_setBuffer(mjFB_OFFSCREEN, &r->con_);
  if (r->con_.currentBuffer != mjFB_OFFSCREEN) {
    *error = "MuJoCo's rendering context has no offscreen buffer";
    return nullptr;
  }
  if (!options.shadows) {
    r->scn_.flags[mjRND_SHADOW] = 0;
    r->scn_.flags[mjRND_REFLECTION] = 0;
  }
  // the clipping planes MuJoCo projects with, to turn the depth buffer into metres
  r->znear_ = m->vis.map.znear * m->stat.extent;
  r->zfar_ = m->vis.map.zfar * m->stat.extent;
  return r;
}

Offscreen::~Offscreen() {
  if (gl_ != nullptr) OSMesaMakeCurrent(static_cast<OSMesaContext>(gl_), gl_buffer_.data(),
                                        GL_UNSIGNED_BYTE, options_.width, options_.height);
  if (context_made_) mjr_freeContext(&con_);
  if (scene_made_) mjv_freeScene(&scn_);
  if (gl_ != nullptr) OSMesaDestroyContext(static_cast<OSMesaContext>(gl_));
}

void Offscreen::Draw(const mjModel* m, mjData* d, mjvCamera* camera, int width, int height) {
  auto* gl = static_cast<OSMesaContext>(gl_);
  if (OSMesaGetCurrentContext() != gl) {
    OSMesaMakeCurrent(gl, gl_buffer_.data(), GL_UNSIGNED_BYTE, options_.width, options_.height);
  }
  const mjrRect viewport{0, 0, std::min(width, options_.width), std::min(height, options_.height)};
  mjv_updateScene(m, d, &opt_, nullptr, camera, mjCAT_ALL, &scn_);
  mjr_render(viewport, &scn_, &con_);
}

void Offscreen::Read(int width, int height, uint8_t* rgb, float* depth) {
  const int w = std::min(width, options_.width), h = std::min(height, options_.height);
  const mjrRect viewport{0, 0, w, h};
  mjr_readPixels(rgb_.data(), depth != nullptr ? depth_.data() : nullptr, viewport, &con_);
  // OpenGL's rows are bottom first
  const std::size_t stride = static_cast<std::size_t>(w) * 3;
  for (int y = 0; y < h; ++y) {
    std::memcpy(rgb + static_cast<std::size_t>(y) * stride,
                rgb_.data() + static_cast<std::size_t>(h - 1 - y) * stride, stride);
  }
  if (depth == nullptr) return;
  // the depth buffer holds the perspective projection's z in [0, 1]: back to metres
  const double n = znear_, f = zfar_;
  for (int y = 0; y < h; ++y) {
    const float* src = depth_.data() + static_cast<std::size_t>(h - 1 - y) * w;
    float* dst = depth + static_cast<std::size_t>(y) * w;
    for (int x = 0; x < w; ++x) dst[x] = static_cast<float>(n / (1.0 - src[x] * (1.0 - n / f)));
  }
}

}  // namespace ohrp::render
