// A sweep's `parameters` (see sweep.h and docs/sweep.md): each entry one parameter or a zip
// group, its values listed, a range or drawn (draw.cc); each entry is one axis of the grid.
#include "spec_parameters.h"

#include <yaml-cpp/yaml.h>

#include <cmath>

#include "draw.h"
#include "keys.h"
#include "yaml_read.h"  // the runner's typed reads (ReadNumber, ReadText, ...)

namespace ohrp::sweep {
namespace {

using runner::KnownKeysOnly;
using runner::ReadInteger;
using runner::ReadNumber;
using runner::ReadText;

const std::set<std::string> kParameterKeys = {"key", "values", "range", "draw", "zip"};
const std::set<std::string> kRangeKeys = {"from", "to", "steps", "scale"};
constexpr long long kMaxSteps = 10000;
constexpr const char* kSweep = "sweep";  // the messages' kind (the runner's reads)

// the range's `steps` values, the ends exactly
void FillRange(double from, double to, long long steps, Parameter* p) {
  for (long long i = 0; i < steps; ++i) {
    const double f = steps == 1 ? 0 : static_cast<double>(i) / static_cast<double>(steps - 1);
    double x = p->log_scale ? std::exp(std::log(from) + f * (std::log(to) - std::log(from)))
                            : from + f * (to - from);
    if (i == 0) x = from;  // the ends exactly
    if (i == steps - 1 && steps > 1) x = to;
    Value v;
    v.numeric = true;
    v.number = x;
    v.text = NumberText(x);
    p->values.push_back(v);
  }
}

// values: a list of scalars
bool ReadValues(const YAML::Node& n, const std::string& path, const std::string& where,
                Parameter* p, std::string* error) {
  std::string why;
  const YAML::Node list = n["values"];
  if (!list.IsSequence() || list.size() == 0) {
    *error = AtKey(path, n, "values") + where + p->key + ": values: must be a non-empty list, e.g. [1e6, 3e6]";
    return false;
  }
  for (size_t i = 0; i < list.size(); ++i) {
    Value v;
    if (!ReadValue(list[i], &v, &why)) {
      *error = At(path, list[i]) + where + p->key + ": values[" + std::to_string(i) + "]: " + why;
      return false;
    }
    p->values.push_back(v);
  }
  return true;
}

// a range: from, to, steps, linear or log
bool ReadRange(const YAML::Node& n, const std::string& path, const std::string& where,
               Parameter* p, std::string* error) {
  std::string why;
  const YAML::Node r = n["range"];
  const std::string rw = where + p->key + ": range: ";
  if (!r.IsMap()) {
    *error = AtKey(path, n, "range") + rw + "must be a mapping, e.g. {from: 1e6, to: 1e7, steps: 5, scale: log}";
    return false;
  }
  if (!KnownKeysOnly(r, kRangeKeys, path, rw, error, kSweep)) return false;
  double from = 0, to = 0;
  long long steps = 0;
  for (const char* k : {"from", "to", "steps"}) {
    if (!r[k]) {
      *error = At(path, r) + rw + "'" + k + "' is required";
      return false;
    }
  }
  if (!ReadNumber(r["from"], &from, &why) || !ReadNumber(r["to"], &to, &why)) {
    *error = AtKey(path, r, ReadNumber(r["from"], &from, &why) ? "to" : "from") + rw + why;
    return false;
  }
  if (!ReadInteger(r["steps"], &steps, &why) || steps < 1 || steps > kMaxSteps) {
    *error = AtKey(path, r, "steps") + rw + "steps: must be a whole number in [1, " +
             std::to_string(kMaxSteps) + "], not '" + r["steps"].Scalar() + "'";
    return false;
  }
  std::string scale = "linear";
  if (r["scale"] && !runner::ReadChoice(r["scale"], {"linear", "log"}, &scale, &why)) {
    *error = AtKey(path, r, "scale") + rw + "scale: " + why;
    return false;
  }
  p->log_scale = scale == "log";
  if (p->log_scale && !(from > 0 && to > 0)) {
    *error = AtKey(path, r, from > 0 ? "to" : "from") + rw + "a log range needs from > 0 and to > 0";
    return false;
  }
  if (steps == 1 && from != to) {
    *error = AtKey(path, r, "steps") + rw + "steps: 1 gives one value: from and to must then be equal";
    return false;
  }
  FillRange(from, to, steps, p);
  return true;
}

// the parameters of one `parameters` entry (one, or a zip group); each group is one axis
bool ReadParameter(const YAML::Node& n, const std::string& path, const std::string& where,
                   bool in_zip, Parameter* p, std::string* error) {
  if (!n.IsMap()) {
    *error = At(path, n) + where + "must be a mapping, e.g. {key: contact_params.stiffness, values: [1e6, 3e6]}";
    return false;
  }
  if (!KnownKeysOnly(n, kParameterKeys, path, where, error, kSweep)) return false;
  p->line = n.Mark().line + 1;
  std::string why;
  if (!n["key"] || !ReadText(n["key"], &p->key, &why) || p->key.empty()) {
    *error = AtKey(path, n, "key") + where + "'key' is required: the scenario key to vary, e.g. contact_params.stiffness";
    return false;
  }
  std::vector<Token> tokens;
  if (!SplitKey(p->key, &tokens, &why)) {
    *error = AtKey(path, n, "key") + where + "key: " + why;
    return false;
  }
  if (in_zip && n["zip"]) {
    *error = AtKey(path, n, "zip") + where + "a zip group cannot hold another";
    return false;
  }
  if (!!n["values"] + !!n["range"] + !!n["draw"] != 1) {
    *error = At(path, n) + where + p->key + ": give one of 'values' (a list), 'range' ({from, to, "
             "steps, scale}) or 'draw' ({distribution, ..., n, seed})";
    return false;
  }
  if (n["draw"]) return ReadDraw(n["draw"], path, where, p, error);
  if (n["values"]) return ReadValues(n, path, where, p, error);
  return ReadRange(n, path, where, p, error);
}

// entry i of the list: a zip group of two or more parameters with as many values each
bool ReadZip(const YAML::Node& entry, const std::string& path, const std::string& where,
             SweepSpec* s, std::vector<size_t>* axis, std::string* error) {
  const YAML::Node zip = entry["zip"];
  if (entry.size() != 1 || !zip.IsSequence() || zip.size() < 2) {
    *error = At(path, entry) + where + "zip: must be the entry's only key, a list of two or more parameters varied together";
    return false;
  }
  for (size_t k = 0; k < zip.size(); ++k) {
    Parameter p;
    if (!ReadParameter(zip[k], path, where + "zip[" + std::to_string(k) + "]: ", true, &p, error)) return false;
    if (!s->parameters.empty() && !axis->empty() && p.values.size() != s->parameters[(*axis)[0]].values.size()) {
      *error = At(path, zip[k]) + where + "zip: " + p.key + " has " + std::to_string(p.values.size()) +
               " values, " + s->parameters[(*axis)[0]].key + " " + std::to_string(s->parameters[(*axis)[0]].values.size()) +
               " (zipped parameters need as many values each)";
      return false;
    }
    axis->push_back(s->parameters.size());
    s->parameters.push_back(p);
  }
  return true;
}

}  // namespace

std::string At(const std::string& path, const YAML::Node& n) { return runner::At(path, n, kSweep); }
std::string AtKey(const std::string& path, const YAML::Node& map, const std::string& key) {
  return runner::AtKey(path, map, key, kSweep);
}

// a scalar as a parameter value: numbers in their shortest exact form
bool ReadValue(const YAML::Node& n, Value* v, std::string* why) {
  if (!ReadText(n, &v->text, why)) return false;
  double x = 0;
  std::string ignored;
  if (n.Tag() != "!" && ReadNumber(n, &x, &ignored)) {  // "!": a quoted scalar stays text
    v->numeric = true;
    v->number = x;
    v->text = NumberText(x);
  }
  return true;
}

bool ReadParameters(const YAML::Node& root, const std::string& path, SweepSpec* s,
                    std::vector<std::vector<size_t>>* axes, std::set<std::string>* keys,
                    std::string* error) {
  const YAML::Node list = root["parameters"];
  if (!list || !list.IsSequence() || list.size() == 0) {
    *error = (list ? AtKey(path, root, "parameters") : "sweep '" + path + "': ") +
             "'parameters' must be a non-empty list, e.g. - {key: contact_params.stiffness, values: [1e6, 3e6]}";
    return false;
  }
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string where = "parameters[" + std::to_string(i) + "]: ";
    std::vector<size_t> axis;
    const YAML::Node zip = list[i].IsMap() ? list[i]["zip"] : YAML::Node();
    if (zip) {
      if (!ReadZip(list[i], path, where, s, &axis, error)) return false;
    } else {
      Parameter p;
      if (!ReadParameter(list[i], path, where, false, &p, error)) return false;
      axis.push_back(s->parameters.size());
      s->parameters.push_back(p);
    }
    for (size_t k : axis) {
      if (!keys->insert(s->parameters[k].key).second) {
        *error = "sweep '" + path + "': line " + std::to_string(s->parameters[k].line) + ": " + where +
                 "'" + s->parameters[k].key + "' is varied twice";
        return false;
      }
    }
    axes->push_back(axis);
  }
  return true;
}

}  // namespace ohrp::sweep
