// Offscreen rendering with MuJoCo's renderer on OSMesa (software OpenGL: no display, no GPU),
// shared by sim_host's cameras (images into the segment) and ohrp_video (videos of a run).
//
// One Offscreen owns an OSMesa context, MuJoCo's abstract scene and its rendering context for
// one model. Draw renders the state of an mjData whose kinematics are computed (mj_kinematics,
// mj_camlight) seen from an mjvCamera (a camera of the model: type mjCAMERA_FIXED and its
// fixedcamid; or a free camera); Read copies the pixels out, top row first, and the depth as
// metres along the camera's optical axis. OSMesa binds the context to the calling thread: use
// an Offscreen from the thread that created it. Draw and Read do not allocate.
#pragma once

#include <mujoco/mujoco.h>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace ohrp::render {

struct OffscreenOptions {
  int width = 640;         // the largest frame drawn [pixel]
  int height = 480;
  bool shadows = false;    // shadows and reflections (in software they cost most of a frame)
  int max_geoms = 4000;    // capacity of MuJoCo's abstract scene
  // multisamples per pixel (MuJoCo's vis.quality.offsamples, set on the model); -1 keeps the
  // model's (4 by default). Camera images use 0: with multisampling the depth read back is one
  // sample's, off the pixel's centre (0.4 % of the range on a floor seen at 30 deg), and each
  // frame costs more
  int samples = -1;
};

class Offscreen {
 public:
  // Creates the context for model `m`. Raises m->vis.global.offwidth/offheight to the size when
  // they are smaller and sets vis.quality.offsamples when asked (MuJoCo sizes its offscreen
  // buffer from them; nothing else reads them).
  // Null with `*error` set when OSMesa or MuJoCo's context cannot be made.
  static std::unique_ptr<Offscreen> Create(mjModel* m, const OffscreenOptions& options,
                                           std::string* error);
  ~Offscreen();
  Offscreen(const Offscreen&) = delete;
  Offscreen& operator=(const Offscreen&) = delete;

  // Renders `d` (kinematics computed) from `camera` into a width x height viewport
  // (<= the options' size).
  void Draw(const mjModel* m, mjData* d, mjvCamera* camera, int width, int height);

  // The last Draw's pixels: `rgb` width x height x 3 bytes, top row first; `depth` (or null)
  // width x height distances along the optical axis [m], same order (the far plane where
  // nothing was drawn).
  void Read(int width, int height, uint8_t* rgb, float* depth);

  mjrContext* context() { return &con_; }  // e.g. for mjr_overlay between Draw and Read
  mjvScene* scene() { return &scn_; }
  const OffscreenOptions& options() const { return options_; }

 private:
  Offscreen() = default;
  OffscreenOptions options_;
  void* gl_ = nullptr;                   // OSMesaContext
  std::vector<unsigned char> gl_buffer_;  // OSMesa's colour buffer (RGBA)
  mjvScene scn_{};
  mjvOption opt_{};
  mjrContext con_{};
  bool scene_made_ = false, context_made_ = false;
  double znear_ = 0.0, zfar_ = 0.0;      // clipping planes [m]
  std::vector<unsigned char> rgb_;       // bottom row first, as OpenGL reads
  std::vector<float> depth_;
};

}  // namespace ohrp::render
