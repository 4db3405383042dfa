// glTF / GLB / OBJ export, validated by reading the files back: a minimal
// JSON parser of the test's own, base64 decoding, and checks of accessor
// counts and bounds against the model.
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <memory>
#include <set>
#include <sstream>

#include "cmkit/tools/export.h"
#include "model_fixtures.h"

namespace cmkit {
namespace {

// ---- a minimal JSON reader (enough for glTF) ---------------------------------

struct JsonValue {
  enum Type { Null, Bool, Number, String, Array, Object } type = Null;
  double number = 0;
  bool boolean = false;
  std::string string;
  std::vector<JsonValue> array;
  std::map<std::string, JsonValue> object;

  const JsonValue& operator[](const std::string& key) const {
    static const JsonValue kMissing;  // NOLINT: test-only sentinel
    auto it = object.find(key);
    return it == object.end() ? kMissing : it->second;
  }
  const JsonValue& operator[](std::size_t i) const { return array.at(i); }
  bool has(const std::string& key) const { return object.count(key) != 0; }
  int asInt() const { return int(number); }
};

/// Reads JSON from a string that must outlive the reader.
class JsonReader {
 public:
  explicit JsonReader(std::string_view text) : s_(text) {}
  JsonValue parse() {
    JsonValue v = value();
    skip();
    if (pos_ != s_.size()) fail("trailing text");
    return v;
  }
  std::string error;

 private:
  void fail(const char* why) {
    if (error.empty()) error = std::string(why) + " at " + std::to_string(pos_);
    pos_ = s_.size();
  }
  void skip() {
    while (pos_ < s_.size() && s_[pos_] != '\0' && std::strchr(" \t\r\n", s_[pos_])) ++pos_;
  }
  bool eat(char c) {
    skip();
    if (pos_ < s_.size() && s_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  std::string str() {
    std::string out;
    if (!eat('"')) fail("expected string");
    while (pos_ < s_.size() && s_[pos_] != '"') {
      char c = s_[pos_++];
      if (c == '\\' && pos_ < s_.size()) {
        c = s_[pos_++];
        if (c == 'u') {
          out += char(std::stoi(std::string(s_.substr(pos_, 4)), nullptr, 16));
          pos_ += 4;
          continue;
        }
        if (c == 'n') c = '\n';
      }
      out += c;
    }
    if (!eat('"')) fail("unterminated string");
    return out;
  }
  JsonValue value() {
    skip();
    JsonValue v;
    if (pos_ >= s_.size()) {
      fail("unexpected end");
      return v;
    }
    const char c = s_[pos_];
    if (c == '{') {
      ++pos_;
      v.type = JsonValue::Object;
      if (eat('}')) return v;
      do {
        std::string k = str();
        if (!eat(':')) fail("expected :");
        v.object[k] = value();
      } while (eat(','));
      if (!eat('}')) fail("expected }");
    } else if (c == '[') {
      ++pos_;
      v.type = JsonValue::Array;
      if (eat(']')) return v;
      do v.array.push_back(value());
      while (eat(','));
      if (!eat(']')) fail("expected ]");
    } else if (c == '"') {
      v.type = JsonValue::String;
      v.string = str();
    } else if (s_.substr(pos_, 4) == "true" || s_.substr(pos_, 5) == "false") {
      v.type = JsonValue::Bool;
      v.boolean = c == 't';
      pos_ += v.boolean ? 4 : 5;
    } else if (s_.substr(pos_, 4) == "null") {
      pos_ += 4;
    } else {
      std::size_t used = 0;
      v.type = JsonValue::Number;
      v.number = std::stod(std::string(s_.substr(pos_, 40)), &used);
      pos_ += used;
    }
    return v;
  }
  std::string_view s_;
  std::size_t pos_ = 0;
};

std::vector<std::uint8_t> decodeBase64(std::string_view text) {
  auto val = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  std::vector<std::uint8_t> out;
  std::uint32_t acc = 0;
  int bits = 0;
  for (char c : text) {
    const int v = val(c);
    if (v < 0) continue;
    acc = acc << 6 | std::uint32_t(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(std::uint8_t(acc >> bits));
    }
  }
  return out;
}

// ---- checks ---------------------------------------------------------------------

constexpr int kTriangles = 4;
constexpr int kLines = 1;

ModelPtr twoBoxes() {
  return std::make_shared<const CollisionModel>(test::ModelMaker()
                                                    .addBox({{-16, -16, -16}, {16, 16, 16}}, contents::kSolid)
                                                    .addBox({{32, 0, 0}, {64, 8, 8}}, contents::kWater)
                                                    .markInternal(1)
                                                    .build());
}

/// Checks every accessor against its buffer view and the buffer; returns
/// the number of triangle vertices, triangle indices and line indices, and
/// the bounds of all POSITION accessors of triangle meshes.
struct Totals {
  std::size_t triangleVertices = 0, triangleIndices = 0, lineIndices = 0;
  Bounds bounds;
  std::set<std::string> materials;
};

Totals checkDocument(const JsonValue& doc, const std::vector<std::uint8_t>& bin) {
  Totals t;
  EXPECT_EQ(doc["asset"]["version"].string, "2.0");
  EXPECT_EQ(std::size_t(doc["buffers"][0]["byteLength"].number), bin.size());
  const auto& accessors = doc["accessors"].array;
  const auto& views = doc["bufferViews"].array;
  for (const JsonValue& a : accessors) {
    const JsonValue& view = views.at(std::size_t(a["bufferView"].asInt()));
    const std::size_t elem = a["type"].string == "VEC3" ? 12 : 4;
    EXPECT_EQ(std::size_t(view["byteLength"].number), std::size_t(a["count"].number) * elem);
    EXPECT_LE(std::size_t(view["byteOffset"].number + view["byteLength"].number), bin.size());
    EXPECT_EQ(std::size_t(view["byteOffset"].number) % 4, 0u);
  }
  for (const JsonValue& m : doc["materials"].array) t.materials.insert(m["name"].string);
  for (const JsonValue& mesh : doc["meshes"].array) {
    for (const JsonValue& prim : mesh["primitives"].array) {
      const JsonValue& pos = accessors.at(std::size_t(prim["attributes"]["POSITION"].asInt()));
      const JsonValue& idx = accessors.at(std::size_t(prim["indices"].asInt()));
      // Indices stay within the vertices; min/max are the real bounds.
      const JsonValue& iv = views.at(std::size_t(idx["bufferView"].asInt()));
      const JsonValue& pv = views.at(std::size_t(pos["bufferView"].asInt()));
      Bounds real;
      for (std::size_t i = 0; i < std::size_t(pos["count"].number); ++i) {
        float xyz[3];
        std::memcpy(xyz, bin.data() + std::size_t(pv["byteOffset"].number) + i * 12, 12);
        real.addPoint({xyz[0], xyz[1], xyz[2]});
      }
      for (int k = 0; k < 3; ++k) {
        EXPECT_EQ(float(pos["min"][std::size_t(k)].number), real.min[k]);
        EXPECT_EQ(float(pos["max"][std::size_t(k)].number), real.max[k]);
      }
      for (std::size_t i = 0; i < std::size_t(idx["count"].number); ++i) {
        std::uint32_t v;
        std::memcpy(&v, bin.data() + std::size_t(iv["byteOffset"].number) + i * 4, 4);
        EXPECT_LT(v, std::uint32_t(pos["count"].number));
      }
      if (prim["mode"].asInt() == kTriangles) {
        t.triangleVertices += std::size_t(pos["count"].number);
        t.triangleIndices += std::size_t(idx["count"].number);
        t.bounds.addBounds(real);
        EXPECT_TRUE(prim["attributes"].has("NORMAL"));
      } else {
        EXPECT_EQ(prim["mode"].asInt(), kLines);
        t.lineIndices += std::size_t(idx["count"].number);
      }
    }
  }
  return t;
}

TEST(DebugExport, GltfRoundTripMatchesTheModel) {
  const ModelPtr m = twoBoxes();
  const std::string text = exportGltf(std::span(&m, 1), {});
  JsonReader reader(text);
  const JsonValue doc = reader.parse();
  ASSERT_TRUE(reader.error.empty()) << reader.error;
  const std::string& uri = doc["buffers"][0]["uri"].string;
  const std::string prefix = "data:application/octet-stream;base64,";
  ASSERT_EQ(uri.rfind(prefix, 0), 0u);
  const Totals t = checkDocument(doc, decodeBase64(std::string_view(uri).substr(prefix.size())));
  // 12 quads: 48 vertices, 2 triangles each.
  EXPECT_EQ(t.triangleVertices, 48u);
  EXPECT_EQ(t.triangleIndices, 12u * 2u * 3u);
  EXPECT_EQ(t.bounds, m->bounds());
  // 24 edges, one internal: 23 edge lines + 1 internal line.
  EXPECT_EQ(t.lineIndices, 24u * 2u);
  EXPECT_TRUE(t.materials.count("contents solid"));
  EXPECT_TRUE(t.materials.count("contents water"));
  // The root node turns z-up into y-up.
  EXPECT_EQ(doc["nodes"][0]["rotation"].array.size(), 4u);
}

TEST(DebugExport, GlbHasTheSameContent) {
  const ModelPtr m = twoBoxes();
  const std::vector<std::uint8_t> glb = exportGlb(std::span(&m, 1), {});
  ASSERT_GE(glb.size(), 28u);
  auto u32 = [&](std::size_t at) {
    std::uint32_t v;
    std::memcpy(&v, glb.data() + at, 4);
    return v;
  };
  EXPECT_EQ(std::memcmp(glb.data(), "glTF", 4), 0);
  EXPECT_EQ(u32(4), 2u);
  EXPECT_EQ(u32(8), glb.size());
  const std::uint32_t jsonLen = u32(12);
  EXPECT_EQ(jsonLen % 4, 0u);
  EXPECT_EQ(std::memcmp(glb.data() + 16, "JSON", 4), 0);
  const std::string json(reinterpret_cast<const char*>(glb.data() + 20), jsonLen);
  const std::size_t binAt = 20 + jsonLen;
  const std::uint32_t binLen = u32(binAt);
  EXPECT_EQ(std::memcmp(glb.data() + binAt + 4, "BIN\0", 4), 0);
  const std::vector<std::uint8_t> bin(glb.begin() + std::ptrdiff_t(binAt + 8),
                                      glb.begin() + std::ptrdiff_t(binAt + 8 + binLen));
  JsonReader reader(json);
  const JsonValue doc = reader.parse();
  ASSERT_TRUE(reader.error.empty()) << reader.error;
  EXPECT_FALSE(doc["buffers"][0].has("uri"));
  const Totals t = checkDocument(doc, bin);
  EXPECT_EQ(t.triangleVertices, 48u);
  EXPECT_EQ(t.bounds, m->bounds());
}

TEST(DebugExport, TracesBecomeNodesWithTheirContact) {
  const ModelPtr m = twoBoxes();
  const auto traces = parseTraceRecords(
      "translation trm=box:-4,-4,-4,4,4,4 start=0,0,100 end=0,0,-100\n",
      "fraction=0.38 endpos=0,0,20.25 endaxis=1,0,0,0,1,0,0,0,1 type=trmvertex point=4,4,16 normal=0,0,1 "
      "dist=16 contents=1 material=- modelfeature=3 trmfeature=5\n");
  const std::string text = exportGltf(std::span(&m, 1), traces);
  JsonReader reader(text);
  const JsonValue doc = reader.parse();
  ASSERT_TRUE(reader.error.empty()) << reader.error;
  const JsonValue* trace = nullptr;
  for (const JsonValue& n : doc["nodes"].array)
    if (n["name"].string == "trace 0") trace = &n;
  ASSERT_NE(trace, nullptr);
  EXPECT_EQ(trace->operator[]("extras")["type"].string, "trmvertex");
  EXPECT_FLOAT_EQ(float(trace->operator[]("extras")["fraction"].number), 0.38f);
  EXPECT_EQ(trace->operator[]("extras")["trmFeature"].asInt(), 5);
  EXPECT_EQ(trace->operator[]("extras")["point"][2].number, 16);
  // Path, trace model, contact marker and normal.
  EXPECT_EQ(trace->operator[]("children").array.size(), 4u);
}

TEST(DebugExport, PlacementMovesTheExportedModel) {
  const ModelPtr m = twoBoxes();
  ExportOptions o;
  o.placements.push_back(Placement{{1000, 0, 0}, Mat3{}});
  const std::string text = exportGltf(std::span(&m, 1), {}, o);
  JsonReader reader(text);
  const JsonValue doc = reader.parse();
  ASSERT_TRUE(reader.error.empty());
  for (const JsonValue& a : doc["accessors"].array)
    if (a.has("min")) {
      EXPECT_GE(a["min"][0].number, 1000 - 16);
    }
}

TEST(DebugExport, ModelNodesNameTheirEntityAndTracesTheEntityHit) {
  // Two models, the second an entity with a class and an origin; a world
  // result's entity= reaches the trace node.
  const ModelPtr models[2] = {twoBoxes(), twoBoxes()};
  ExportOptions o;
  o.placements = {Placement{}, Placement{{0, 500, 0}, Mat3{}}};
  o.classNames = {"worldspawn", "func_door"};
  const auto traces =
      parseTraceRecords("translation trm=point start=0,0,100 end=0,0,-100\n",
                        "fraction=0.42 endpos=0,0,16 type=modelvertex point=0,0,16 normal=0,0,1 "
                        "dist=16 contents=1 entity=door1\n");
  const std::string text = exportGltf(models, traces, o);
  JsonReader reader(text);
  const JsonValue doc = reader.parse();
  ASSERT_TRUE(reader.error.empty()) << reader.error;
  int doorParts = 0;
  bool traceNamesDoor = false;
  for (const JsonValue& n : doc["nodes"].array) {
    if (!n.has("extras")) continue;
    const JsonValue& x = n["extras"];
    if (x.has("modelIndex") && x["modelIndex"].asInt() == 1) {
      ++doorParts;
      EXPECT_EQ(x["classname"].string, "func_door");
      EXPECT_EQ(x["origin"][1].number, 500);
    } else if (x.has("modelIndex")) {
      EXPECT_EQ(x["modelIndex"].asInt(), 0);
      EXPECT_EQ(x["classname"].string, "worldspawn");
    }
    if (n["name"].string == "trace 0") traceNamesDoor = x["entity"].string == "door1";
  }
  EXPECT_GE(doorParts, 2);  // its polygons and its edges at least
  EXPECT_TRUE(traceNamesDoor);
}

TEST(DebugExport, ObjCountsMatchTheModel) {
  const ModelPtr m = twoBoxes();
  const std::string obj = exportObj(std::span(&m, 1), {}, "scene.mtl");
  std::istringstream in(obj);
  int v = 0, vn = 0, f = 0, l = 0, usemtl = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("v ", 0) == 0) ++v;
    if (line.rfind("vn ", 0) == 0) ++vn;
    if (line.rfind("f ", 0) == 0) ++f;
    if (line.rfind("l ", 0) == 0) ++l;
    if (line.rfind("usemtl ", 0) == 0) ++usemtl;
  }
  EXPECT_EQ(vn, 48);
  EXPECT_EQ(f, 24);
  EXPECT_EQ(l, 24);
  EXPECT_EQ(v, 48 + 48);
  const std::string mtl = exportMtl(std::span(&m, 1), {});
  EXPECT_NE(mtl.find("newmtl contents_solid"), std::string::npos);
  EXPECT_NE(mtl.find("newmtl contents_water"), std::string::npos);
}

TEST(DebugExport, SaveSceneRejectsUnknownExtensions) {
  const ModelPtr m = twoBoxes();
  EXPECT_FALSE(saveScene("/tmp/cmkit_scene.xyz", std::span(&m, 1), {}));
}

}  // namespace
}  // namespace cmkit
