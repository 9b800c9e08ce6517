// VRML97 parser (see syntax.h): PROTO declarations give a node type its fields and defaults;
// the standard nodes the converter reads have theirs below; other standard nodes (Viewpoint,
// Background, ...) are parsed and their fields kept unchecked.
#include <set>

#include "vrml/syntax.h"

namespace ohrp::vrml {
namespace {

constexpr int kMaxDepth = 100;  // nesting of nodes and lists the parser accepts

// a node type: its field names and default values
struct NodeType {
  std::set<std::string> names;
  std::map<std::string, Value> defaults;
};

Value Numbers(std::vector<double> v) {
  Value out;
  out.numbers = std::move(v);
  return out;
}

// the standard VRML97 nodes the converter interprets, with the defaults it uses
std::map<std::string, NodeType> StandardNodes() {
  std::map<std::string, NodeType> s;
  auto add = [&s](const std::string& type, std::vector<std::string> names,
                  std::map<std::string, Value> defaults) {
    NodeType& t = s[type];
    t.names.insert(names.begin(), names.end());
    t.defaults = std::move(defaults);
  };
  add("Transform",
      {"translation", "rotation", "scale", "scaleOrientation", "center", "children",
       "bboxCenter", "bboxSize", "addChildren", "removeChildren"},
      {{"translation", Numbers({0, 0, 0})}, {"rotation", Numbers({0, 0, 1, 0})},
       {"scale", Numbers({1, 1, 1})}, {"center", Numbers({0, 0, 0})}});
  add("Group", {"children", "bboxCenter", "bboxSize", "addChildren", "removeChildren"}, {});
  add("Shape", {"appearance", "geometry"}, {});
  add("Box", {"size"}, {{"size", Numbers({2, 2, 2})}});
  add("Cylinder", {"radius", "height", "side", "top", "bottom"},
      {{"radius", Numbers({1})}, {"height", Numbers({2})}});
  add("Sphere", {"radius"}, {{"radius", Numbers({1})}});
  add("IndexedFaceSet",
      {"coord", "coordIndex", "ccw", "solid", "convex", "creaseAngle", "color", "colorIndex",
       "colorPerVertex", "normal", "normalIndex", "normalPerVertex", "texCoord", "texCoordIndex",
       "set_coordIndex", "set_colorIndex", "set_normalIndex", "set_texCoordIndex"},
      {});
  add("Coordinate", {"point"}, {});
  add("Appearance", {"material", "texture", "textureTransform"}, {});
  add("Material",
      {"diffuseColor", "ambientIntensity", "specularColor", "emissiveColor", "shininess",
       "transparency"},
      {{"diffuseColor", Numbers({0.8, 0.8, 0.8})}, {"transparency", Numbers({0})}});
  add("Inline", {"url", "bboxCenter", "bboxSize"}, {});
  return s;
}

std::string Describe(const Token& t) {
  switch (t.kind) {
    case Token::kEnd: return "the end of the file";
    case Token::kString: return "the string \"" + t.text + "\"";
    default: return "'" + t.text + "'";
  }
}

class Parser {
 public:
  Parser(const std::vector<Token>& tokens, std::string* error)
      : t_(tokens), error_(error), standard_(StandardNodes()) {}

  // file: PROTO, EXTERNPROTO, ROUTE and nodes
  bool File(Document* doc) {
    while (Peek().kind != Token::kEnd) {
      const Token& t = Peek();
      if (IsWord(t, "PROTO")) {
        if (!Proto()) return false;
      } else if (IsWord(t, "EXTERNPROTO")) {
        if (!ExternProto()) return false;
      } else if (IsWord(t, "ROUTE")) {
        if (!Route()) return false;
      } else {
        NodePtr node;
        if (!NodeValue(&node, /*top_level=*/true)) return false;
        if (!node) continue;
        if (node->type == "Inline") {
          const Value* url = node->Field("url");
          if (!url || url->kind != Value::kStrings || url->strings.empty())
            return Fail(node->at, "Inline needs a url, e.g. Inline { url \"floor.wrl\" }");
          doc->inlines.push_back({url->strings[0], node->at});
        } else {
          doc->roots.push_back(node);
        }
      }
    }
    return true;
  }

 private:
  const Token& Peek(size_t k = 0) const {
    const size_t j = i_ + k;
    return j < t_.size() ? t_[j] : t_.back();
  }
  const Token& Next() {
    const Token& t = Peek();
    if (i_ < t_.size() - 1) ++i_;
    return t;
  }
  static bool IsWord(const Token& t, const char* w) { return t.kind == Token::kWord && t.text == w; }

  bool Fail(const Where& at, const std::string& what) {
    *error_ = At(at) + what;
    return false;
  }
  bool Expect(Token::Kind kind, const char* what, Token* out = nullptr) {
    const Token& t = Next();
    if (t.kind != kind) return Fail(t.at, std::string("expected ") + what + ", found " + Describe(t));
    if (out) *out = t;
    return true;
  }

  // ROUTE a.b TO c.d: routes are events, nothing to model
  bool Route() {
    Next();
    for (int k = 0; k < 3; ++k)
      if (!Expect(Token::kWord, "a ROUTE of the form ROUTE a.field TO b.field")) return false;
    return true;
  }

  // a balanced { ... } or [ ... ]
  bool SkipBalanced(Token::Kind open, Token::Kind close) {
    const Token start = Peek();
    if (!Expect(open, open == Token::kOpenBrace ? "'{'" : "'['")) return false;
    int depth = 1;
    while (depth > 0) {
      const Token& t = Next();
      if (t.kind == Token::kEnd) return Fail(start.at, "this bracket is never closed");
      if (t.kind == open) ++depth;
      if (t.kind == close) --depth;
    }
    return true;
  }

  // PROTO Name [ field declarations ] { body }: the body is not interpreted; the type's
  // meaning comes from its name (Joint, Segment, ...)
  bool Proto() {
    Next();
    Token name;
    if (!Expect(Token::kWord, "the PROTO's name", &name)) return false;
    if (!Expect(Token::kOpenBracket, "'[' after the PROTO's name")) return false;
    NodeType type;
    while (Peek().kind != Token::kCloseBracket) {
      Token kind, ftype, fname;
      if (!Expect(Token::kWord, "field, exposedField, eventIn or eventOut", &kind)) return false;
      if (kind.text != "field" && kind.text != "exposedField" && kind.text != "eventIn" &&
          kind.text != "eventOut")
        return Fail(kind.at, "expected field, exposedField, eventIn or eventOut, found '" +
                                 kind.text + "'");
      if (!Expect(Token::kWord, "a field type (SFFloat, MFNode, ...)", &ftype)) return false;
      if (!Expect(Token::kWord, "a field name", &fname)) return false;
      type.names.insert(fname.text);
      if (kind.text == "field" || kind.text == "exposedField") {
        Value v;
        if (!FieldValue(&v, 0)) return false;
        type.defaults[fname.text] = std::move(v);
      }
    }
    Next();
    if (!SkipBalanced(Token::kOpenBrace, Token::kCloseBrace)) return false;
    protos_[name.text] = std::move(type);
    return true;
  }

  // EXTERNPROTO Name [ declarations ] "url": its fields are known, its defaults are not
  bool ExternProto() {
    Next();
    Token name;
    if (!Expect(Token::kWord, "the EXTERNPROTO's name", &name)) return false;
    if (!Expect(Token::kOpenBracket, "'[' after the EXTERNPROTO's name")) return false;
    NodeType type;
    while (Peek().kind != Token::kCloseBracket) {
      Token kind, ftype, fname;
      if (!Expect(Token::kWord, "field, exposedField, eventIn or eventOut", &kind) ||
          !Expect(Token::kWord, "a field type", &ftype) ||
          !Expect(Token::kWord, "a field name", &fname))
        return false;
      type.names.insert(fname.text);
    }
    Next();
    Value url;
    if (!FieldValue(&url, 0)) return false;
    protos_[name.text] = std::move(type);
    return true;
  }

  // DEF name Type { fields }, USE name, NULL
  bool NodeValue(NodePtr* out, bool top_level, int depth = 0) {
    if (depth > kMaxDepth) return Fail(Peek().at, "nodes nested too deep (more than 100)");
    Token t = Next();
    if (IsWord(t, "NULL")) {
      out->reset();
      return true;
    }
    if (IsWord(t, "USE")) {
      Token name;
      if (!Expect(Token::kWord, "a DEF name after USE", &name)) return false;
      auto it = defs_.find(name.text);
      if (it == defs_.end())
        return Fail(name.at, "USE " + name.text + ": no node was defined as DEF " + name.text +
                                 " before this point");
      *out = it->second;
      return true;
    }
    std::string def_name;
    if (IsWord(t, "DEF")) {
      Token name;
      if (!Expect(Token::kWord, "a name after DEF", &name)) return false;
      def_name = name.text;
      t = Next();
    }
    if (t.kind != Token::kWord)
      return Fail(t.at, "expected a node (a type name such as Transform or Joint), found " +
                            Describe(t));
    auto node = std::make_shared<Node>();
    node->type = t.text;
    node->def_name = def_name;
    node->at = t.at;
    if (node->type == "Inline" && !top_level)
      return Fail(t.at, "Inline is read only at the top level of a file");
    // the type's fields: a PROTO of this file, else a standard node
    const NodeType* type = nullptr;
    if (auto p = protos_.find(node->type); p != protos_.end()) {
      type = &p->second;
    } else if (auto s = standard_.find(node->type); s != standard_.end()) {
      type = &s->second;
    }
    if (type) node->fields = type->defaults;
    if (!Expect(Token::kOpenBrace, ("'{' after " + node->type).c_str())) return false;
    while (Peek().kind != Token::kCloseBrace) {
      const Token& f = Peek();
      if (IsWord(f, "ROUTE")) {
        if (!Route()) return false;
        continue;
      }
      if (IsWord(f, "PROTO") || IsWord(f, "EXTERNPROTO")) {
        if (!(IsWord(f, "PROTO") ? Proto() : ExternProto())) return false;
        continue;
      }
      Token name = Next();
      if (name.kind != Token::kWord)
        return Fail(name.at, "expected a field name of " + node->type + " or '}', found " +
                                 Describe(name));
      if (type && !type->names.count(name.text)) {
        std::string known;
        for (const auto& n : type->names) {
          if (!known.empty()) known += ' ';
          known += n;
        }
        return Fail(name.at, node->type + " has no field '" + name.text + "' (its fields: " +
                                 known + ")");
      }
      Value v;
      if (!FieldValue(&v, depth + 1)) return false;
      node->fields[name.text] = std::move(v);
    }
    Next();
    if (!def_name.empty()) defs_[def_name] = node;  // after its body: a node cannot USE itself
    *out = node;
    return true;
  }

  // one value: numbers, a string, TRUE/FALSE, a node, or a [ list ] of one of these
  bool FieldValue(Value* v, int depth) {
    if (depth > kMaxDepth) return Fail(Peek().at, "values nested too deep (more than 100)");
    v->at = Peek().at;
    if (Peek().kind == Token::kOpenBracket) {
      Next();
      bool first = true;
      while (Peek().kind != Token::kCloseBracket) {
        if (Peek().kind == Token::kEnd) return Fail(v->at, "this '[' is never closed");
        Value item;
        if (!Single(&item, depth)) return false;
        if (!first && item.kind != v->kind)
          return Fail(item.at, "a list mixes kinds of values (numbers, strings, nodes)");
        if (first) v->kind = item.kind;
        first = false;
        v->numbers.insert(v->numbers.end(), item.numbers.begin(), item.numbers.end());
        v->strings.insert(v->strings.end(), item.strings.begin(), item.strings.end());
        v->nodes.insert(v->nodes.end(), item.nodes.begin(), item.nodes.end());
      }
      Next();
      return true;
    }
    return Single(v, depth);
  }

  bool Single(Value* v, int depth) {
    const Token& t = Peek();
    v->at = t.at;
    switch (t.kind) {
      case Token::kNumber:
        v->kind = Value::kNumbers;
        while (Peek().kind == Token::kNumber) v->numbers.push_back(Next().number);
        return true;
      case Token::kString:
        v->kind = Value::kStrings;
        v->strings.push_back(Next().text);
        return true;
      case Token::kWord: {
        if (t.text == "TRUE" || t.text == "FALSE") {
          v->kind = Value::kBool;
          v->boolean = Next().text == "TRUE";
          return true;
        }
        if (t.text == "IS") return Fail(t.at, "IS is allowed only inside a PROTO's body");
        v->kind = Value::kNodes;
        NodePtr node;
        if (!NodeValue(&node, false, depth + 1)) return false;
        if (node) v->nodes.push_back(node);
        return true;
      }
      default:
        return Fail(t.at, "expected a value (numbers, a string, TRUE/FALSE or a node), found " +
                              Describe(t));
    }
  }

  const std::vector<Token>& t_;
  size_t i_ = 0;
  std::string* error_;
  std::map<std::string, NodeType> standard_;
  std::map<std::string, NodeType> protos_;
  std::map<std::string, NodePtr> defs_;
};

}  // namespace

//---------------- node accessors ----------------

const Value* Node::Field(const std::string& name) const {
  auto it = fields.find(name);
  return it == fields.end() ? nullptr : &it->second;
}

double Node::Number(const std::string& name, double fallback) const {
  const Value* v = Field(name);
  return v && v->kind == Value::kNumbers && !v->numbers.empty() ? v->numbers[0] : fallback;
}

std::string Node::String(const std::string& name, const std::string& fallback) const {
  const Value* v = Field(name);
  return v && v->kind == Value::kStrings && !v->strings.empty() ? v->strings[0] : fallback;
}

const std::vector<NodePtr>& Node::Nodes(const std::string& name) const {
  static const std::vector<NodePtr> kNone;
  const Value* v = Field(name);
  return v && v->kind == Value::kNodes ? v->nodes : kNone;
}

bool Parse(const std::vector<Token>& tokens, Document* doc, std::string* error) {
  *doc = Document{};
  if (tokens.empty()) return true;
  Parser p(tokens, error);
  return p.File(doc);
}

}  // namespace ohrp::vrml
