// Reading VRML files (the main file and its Inline files) and loading the MJCF made from them
// through MuJoCo's virtual file system (see vrml/vrml.h).
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>

#include "vrml/mjcf_writer.h"
#include "vrml/model_tree.h"
#include "vrml/syntax.h"
#include "vrml/vrml.h"

namespace ohrp::vrml {
namespace {

constexpr int kMaxFiles = 32;  // files one scene may Inline, all levels together

// the file's canonical name where the file system gives one (never throws)
std::string Canonical(const std::string& path) {
  std::error_code ec;
  const std::filesystem::path p = std::filesystem::weakly_canonical(path, ec);
  return ec ? path : p.string();
}

bool ReadText(const std::string& path, std::string* text, std::string* error) {
  std::error_code ec;
  std::ifstream in(path, std::ios::binary);
  if (!std::filesystem::is_regular_file(path, ec) || !in) {
    *error = "cannot read VRML file '" + path + "'";
    return false;
  }
  std::ostringstream s;
  s << in.rdbuf();
  *text = s.str();
  return true;
}

// one file parsed, then the files it Inlines (depth first), each once
bool ParseTree(const std::string& text, const std::string& file, bool read_inlines,
               std::vector<SourceDocument>* docs, std::vector<std::string>* seen,
               std::string* error) {
  std::vector<Token> tokens;
  SourceDocument src;
  src.file = file;
  if (!Tokenize(text, &tokens, error) || !Parse(tokens, &src.doc, error)) {
    *error = file + ":" + *error;
    return false;
  }
  const std::vector<InlineRef> inlines = src.doc.inlines;
  docs->push_back(std::move(src));
  for (const InlineRef& ref : inlines) {
    const std::string where = file + ":" + At(ref.at);
    if (!read_inlines) {
      *error = where + "Inline \"" + ref.url + "\" is not read here (no files)";
      return false;
    }
    std::string url = ref.url;
    if (url.rfind("file://", 0) == 0) url = url.substr(7);
    const std::filesystem::path base = std::filesystem::path(file).parent_path();
    const std::string path = std::filesystem::path(url).is_absolute() ? url : (base / url).string();
    const std::string key = Canonical(path);
    if (std::find(seen->begin(), seen->end(), key) != seen->end()) {
      *error = where + "Inline \"" + ref.url + "\" is already part of the scene (a loop?)";
      return false;
    }
    if (static_cast<int>(seen->size()) >= kMaxFiles) {
      *error = where + "more than " + std::to_string(kMaxFiles) + " Inline files";
      return false;
    }
    seen->push_back(key);
    std::string inner;
    std::string read_error;
    if (!ReadText(path, &inner, &read_error)) {
      *error = where + "Inline: " + read_error + " (urls are relative to this file)";
      return false;
    }
    if (!ParseTree(inner, path, true, docs, seen, error)) return false;
  }
  return true;
}

bool Convert(const std::string& text, const std::string& file, bool read_inlines,
             std::string* mjcf, std::string* error) {
  std::vector<SourceDocument> docs;
  std::vector<std::string> seen;
  if (read_inlines) seen.push_back(Canonical(file));
  if (!ParseTree(text, file, read_inlines, &docs, &seen, error)) return false;
  Model model;
  if (!BuildModel(docs, &model, error)) return false;
  return WriteMjcf(&model, mjcf, error);
}

struct VfsDeleter {
  void operator()(mjVFS* vfs) const {
    mj_deleteVFS(vfs);
    delete vfs;
  }
};

}  // namespace

bool IsVrmlPath(const std::string& path) {
  if (path.size() < 4) return false;
  std::string ext = path.substr(path.size() - 4);
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext == ".wrl";
}

bool ConvertText(const std::string& text, const std::string& file, std::string* mjcf,
                 std::string* error) {
  return Convert(text, file, /*read_inlines=*/false, mjcf, error);
}

bool ConvertFile(const std::string& path, std::string* mjcf, std::string* error) {
  std::string text;
  if (!ReadText(path, &text, error)) return false;
  return Convert(text, path, /*read_inlines=*/true, mjcf, error);
}

mjModel* LoadModel(const std::string& path, std::string* error) {
  std::string mjcf;
  if (!ConvertFile(path, &mjcf, error)) return nullptr;
  // the MJCF goes to MuJoCo as a buffer of its virtual file system, never to disk
  std::unique_ptr<mjVFS, VfsDeleter> vfs(new mjVFS);
  mj_defaultVFS(vfs.get());
  const char* kName = "vrml_model.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), kName, static_cast<int>(mjcf.size())) != 0) {
    *error = "cannot make the in-memory MJCF of '" + path + "' (MuJoCo's VFS is full)";
    return nullptr;
  }
  const int file = mj_findFileVFS(vfs.get(), kName);
  std::copy(mjcf.begin(), mjcf.end(), static_cast<char*>(vfs->filedata[file]));
  char err[1024] = "";
  mjModel* m = mj_loadXML(kName, vfs.get(), err, sizeof(err));
  if (!m) {
    *error = "cannot load '" + path + "' (MJCF made from the VRML): " +
             (err[0] ? err : "unknown MuJoCo error");
  }
  return m;
}

}  // namespace ohrp::vrml
