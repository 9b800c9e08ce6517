// A sweep folder read back without its sweep file (--gather, --resume), and Slurm's array limit
// (see sweep.h).
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sweep/sweep.h"

namespace fs = std::filesystem;

namespace ohrp::sweep {
namespace {

bool ReadObject(const std::string& path, nlohmann::json* out, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = "cannot read " + path + " (not a sweep folder?)";
    return false;
  }
  try {
    in >> *out;
  } catch (const std::exception& e) {
    *error = path + ": " + e.what();
    return false;
  }
  if (!out->is_object()) {
    *error = path + ": not a JSON object";
    return false;
  }
  return true;
}

Value ValueOf(const std::string& text) {
  Value v;
  v.text = text;
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  v.numeric = !text.empty() && end == text.c_str() + text.size();
  v.number = v.numeric ? x : 0;
  return v;
}

}  // namespace

bool LoadSweepFolder(const std::string& out_dir, SweepSpec* out, std::string* error) {
  const std::string sweep_json = (fs::path(out_dir) / "sweep.json").string();
  nlohmann::json j;
  if (!ReadObject(sweep_json, &j, error)) return false;
  SweepSpec s;
  try {
    s.file = j.value("sweep_file", std::string());
    s.name = j.value("name", std::string("sweep"));
    s.scenario_file = j.value("scenario_file", std::string());
    s.time_limit = j.value("time_limit", 0.0);
    for (const auto& p : j.at("parameters")) {
      Parameter param;
      param.key = p.at("key").get<std::string>();
      param.log_scale = p.value("log_scale", false);
      param.draw = p.value("draw", std::string());
      for (const auto& v : p.at("values")) param.values.push_back(ValueOf(v.get<std::string>()));
      s.parameters.push_back(param);
    }
    for (const auto& p : j.value("plots", nlohmann::json::array()))
      s.plots.push_back({p.at("check").get<std::string>(), p.at("against").get<std::string>(), 0});
    const int n = j.at("variants").get<int>();
    for (int id = 0; id < n; ++id) {
      const std::string path = VariantDir(out_dir, id) + "/variant.json";
      nlohmann::json vj;
      if (!ReadObject(path, &vj, error)) return false;
      Variant v;
      v.id = id;
      for (size_t k = 0; k < s.parameters.size(); ++k) {
        const Parameter& param = s.parameters[k];
        int index = -1;
        if (vj.contains("value_index")) {
          index = vj.at("value_index").at(k).get<int>();
        } else {  // a folder of an earlier ohrp_sweep: the value's text
          const std::string text = vj.at("parameters").at(param.key).get<std::string>();
          for (size_t i = 0; i < param.values.size() && index < 0; ++i)
            if (param.values[i].text == text) index = static_cast<int>(i);
        }
        if (index < 0 || index >= static_cast<int>(param.values.size())) {
          *error = path + ": no value of " + param.key + " in sweep.json";
          return false;
        }
        v.value_index.push_back(index);
      }
      s.variants.push_back(v);
    }
  } catch (const std::exception& e) {
    *error = sweep_json + " or a variant.json: " + e.what();
    return false;
  }
  *out = s;
  return true;
}

std::vector<int> UnfinishedVariants(const SweepSpec& spec, const std::string& out_dir) {
  std::vector<int> ids;
  for (const auto& v : spec.variants) {
    std::ifstream in(VariantDir(out_dir, v.id) + "/status.json");
    nlohmann::json st;
    bool finished = false;
    if (in) {
      try {
        in >> st;
        const auto c = st.find("cancelled");
        finished = st.is_object() && !(c != st.end() && c->is_boolean() && c->get<bool>());
      } catch (const std::exception&) {
        finished = false;  // half a status: run it again
      }
    }
    if (!finished) ids.push_back(v.id);
  }
  return ids;
}

std::vector<ArrayChunk> ChunkArray(std::vector<int> ids, int max_array_size) {
  std::sort(ids.begin(), ids.end());
  std::vector<ArrayChunk> chunks;
  const int m = std::max(1, max_array_size);
  for (size_t i = 0; i < ids.size();) {
    ArrayChunk c;
    c.offset = ids[i] / m * m;
    // the ids of this chunk, as ranges of consecutive task indices
    while (i < ids.size() && ids[i] < c.offset + m) {
      size_t j = i;
      while (j + 1 < ids.size() && ids[j + 1] == ids[j] + 1 && ids[j + 1] < c.offset + m) ++j;
      if (!c.indices.empty()) c.indices += ',';
      c.indices += std::to_string(ids[i] - c.offset);
      if (j > i) {
        c.indices += '-';  // appended piece by piece (GCC 12 warns falsely on "x" + std::string)
        c.indices += std::to_string(ids[j] - c.offset);
      }
      c.count += static_cast<int>(j - i + 1);
      i = j + 1;
    }
    chunks.push_back(c);
  }
  return chunks;
}

int ParseMaxArraySize(const std::string& config) {
  std::istringstream in(config);
  for (std::string line; std::getline(in, line);) {
    const auto k = line.find("MaxArraySize");
    const auto eq = line.find('=');
    if (k == std::string::npos || eq == std::string::npos || eq < k) continue;
    const int v = std::atoi(line.c_str() + eq + 1);
    return v > 0 ? v : 0;
  }
  return 0;
}

}  // namespace ohrp::sweep
