// The cameras' images of a replayed run (source.h, ReplaySource::LoadImages): the index
// RUN_DIR/images/images.csv that sim_host --record-images writes (time, camera, rgb, depth),
// sent to the page as each camera's frame times and files; the server serves those files only.
#include <fstream>
#include <sstream>

#include "view/source.h"

namespace ohrp::view {

void ReplaySource::LoadImages(const std::string& run_dir) {
  images_dir_ = run_dir + "/images";
  std::ifstream in(images_dir_ + "/images.csv");
  if (!in) {
    images_ = {{"note", "no recorded images (sim_host --record-images DIR/images keeps them)"}};
    return;
  }
  std::string line;
  std::getline(in, line);
  if (line != "time,camera,rgb,depth") {
    images_ = {{"note", images_dir_ + "/images.csv is not an index of sim_host --record-images"}};
    return;
  }
  nlohmann::json frames = nlohmann::json::object();
  std::vector<std::string> cameras;
  int row = 1;
  while (std::getline(in, line)) {
    ++row;
    std::stringstream cells(line);
    std::string time, camera, rgb, depth;
    std::getline(cells, time, ',');
    std::getline(cells, camera, ',');
    std::getline(cells, rgb, ',');
    std::getline(cells, depth, ',');
    char* end = nullptr;
    const double t = std::strtod(time.c_str(), &end);
    // a file name of the index: inside the folder, no way out of it
    auto inside = [](const std::string& f) {
      return !f.empty() && f[0] != '/' && f.find("..") == std::string::npos;
    };
    if (camera.empty() || end == time.c_str() || *end != 0 || !inside(rgb) ||
        (!depth.empty() && !inside(depth))) {
      images_ = {{"note", images_dir_ + "/images.csv: line " + std::to_string(row) + " is not time,camera,rgb,depth"}};
      image_files_.clear();
      return;
    }
    if (!frames.contains(camera)) {
      cameras.push_back(camera);
      frames[camera] = {{"t", nlohmann::json::array()}, {"rgb", nlohmann::json::array()}};
    }
    frames[camera]["t"].push_back(t);
    frames[camera]["rgb"].push_back(rgb);
    image_files_.insert(rgb);
    if (!depth.empty()) image_files_.insert(depth);
  }
  images_ = {{"cameras", cameras}, {"frames", frames}};
}

bool ReplaySource::RecordedImage(const std::string& name, std::string* path) const {
  if (image_files_.count(name) == 0) return false;
  *path = images_dir_ + "/" + name;
  return true;
}

}  // namespace ohrp::view
