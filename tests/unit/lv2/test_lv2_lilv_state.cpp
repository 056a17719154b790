// The plugin's state through lilv, the host library under jalv, lv2apply,
// Carla and others: one session (its own lilv world, URID map and worker)
// sets a SOFA set, the controls and a tracker spec, renders, and saves its
// state to a directory as lilv writes it; a second session (a fresh world
// and map) loads that directory, restores it into a new instance and
// renders the same input: the output must be the same, sample for sample.
#include <gtest/gtest.h>
#include <lilv/lilv.h>
#include <lv2/atom/forge.h>
#include <lv2/patch/patch.h>
#include <lv2/state/state.h>
#include <lv2/urid/urid.h>
#include <lv2/worker/worker.h>

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

constexpr double kRate = 48000.0;
constexpr std::uint32_t kBlock = 256;
constexpr const char* kUri = "urn:earshot:lv2:panner";

/// A URID map and unmap, one per session.
struct Urids {
  std::vector<std::string> uris;
  LV2_URID_Map map{this, [](LV2_URID_Map_Handle h, const char* uri) -> LV2_URID {
                     auto& u = static_cast<Urids*>(h)->uris;
                     for (std::size_t i = 0; i < u.size(); ++i)
                       if (u[i] == uri) return static_cast<LV2_URID>(i + 1);
                     u.emplace_back(uri);
                     return static_cast<LV2_URID>(u.size());
                   }};
  LV2_URID_Unmap unmap{this, [](LV2_URID_Unmap_Handle h, LV2_URID id) -> const char* {
                         auto& u = static_cast<Urids*>(h)->uris;
                         return id >= 1 && id <= u.size() ? u[id - 1].c_str() : nullptr;
                       }};
};

/// One host session: a lilv world with the build tree's bundle, an instance,
/// a worker run between blocks, control values by port symbol.
class Session {
 public:
  Session() : world_(lilv_world_new()) {
    LilvNode* bundle = lilv_new_file_uri(world_, nullptr, (std::string(EARSHOT_LV2_BUNDLE) + "/").c_str());
    lilv_world_load_bundle(world_, bundle);
    lilv_node_free(bundle);
    LilvNode* uri = lilv_new_uri(world_, kUri);
    plugin_ = lilv_plugins_get_by_uri(lilv_world_get_all_plugins(world_), uri);
    lilv_node_free(uri);
    if (!plugin_) return;
    schedule_ = {this, [](LV2_Worker_Schedule_Handle h, std::uint32_t size, const void* data) {
                   auto* s = static_cast<Session*>(h);
                   const auto* b = static_cast<const std::uint8_t*>(data);
                   s->jobs_.emplace_back(b, b + size);
                   return LV2_WORKER_SUCCESS;
                 }};
    map_feature_ = {LV2_URID__map, &urids_.map};
    unmap_feature_ = {LV2_URID__unmap, &urids_.unmap};
    schedule_feature_ = {LV2_WORKER__schedule, &schedule_};
    features_ = {&map_feature_, &unmap_feature_, &schedule_feature_, nullptr};
    instance_ = lilv_plugin_instantiate(plugin_, kRate, features_.data());
    if (!instance_) return;
    const std::uint32_t n = lilv_plugin_get_num_ports(plugin_);
    values_.assign(n, 0.0f);
    std::vector<float> defaults(n);
    lilv_plugin_get_port_ranges_float(plugin_, nullptr, nullptr, defaults.data());
    for (std::uint32_t i = 0; i < n; ++i) {
      const LilvPort* port = lilv_plugin_get_port_by_index(plugin_, i);
      symbols_[lilv_node_as_string(lilv_port_get_symbol(plugin_, port))] = i;
      if (!std::isnan(defaults[i])) values_[i] = defaults[i];
      lilv_instance_connect_port(instance_, i, &values_[i]);
    }
    lilv_instance_connect_port(instance_, symbols_.at("in"), in_.data());
    lilv_instance_connect_port(instance_, symbols_.at("out_left"), left_.data());
    lilv_instance_connect_port(instance_, symbols_.at("out_right"), right_.data());
    lilv_instance_connect_port(instance_, symbols_.at("control"), control_.data());
    lilv_instance_connect_port(instance_, symbols_.at("notify"), notify_.data());
    clear_control();
    lilv_instance_activate(instance_);
  }
  ~Session() {
    if (instance_) {
      lilv_instance_deactivate(instance_);
      lilv_instance_free(instance_);
    }
    lilv_world_free(world_);
  }
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;

  [[nodiscard]] bool ok() const {
    if (!plugin_) ADD_FAILURE() << "lilv found no " << kUri << " in " << EARSHOT_LV2_BUNDLE;
    return instance_ != nullptr;
  }
  float& control(const std::string& symbol) { return values_.at(symbols_.at(symbol)); }

  /// Sends patch:Set of `property` to `value` (of `type`) with the next block
  /// (one message per block: each call starts the sequence afresh).
  void patch_set(const std::string& property, const std::string& value, const char* type) {
    LV2_Atom_Forge forge;
    lv2_atom_forge_init(&forge, &urids_.map);
    lv2_atom_forge_set_buffer(&forge, reinterpret_cast<std::uint8_t*>(control_.data()), sizeof control_);
    LV2_Atom_Forge_Frame seq, obj;
    lv2_atom_forge_sequence_head(&forge, &seq, 0);
    lv2_atom_forge_frame_time(&forge, 0);
    lv2_atom_forge_object(&forge, &obj, 0, map(LV2_PATCH__Set));
    lv2_atom_forge_key(&forge, map(LV2_PATCH__property));
    lv2_atom_forge_urid(&forge, map(property.c_str()));
    lv2_atom_forge_key(&forge, map(LV2_PATCH__value));
    lv2_atom_forge_typed_string(&forge, map(type), value.c_str(), static_cast<std::uint32_t>(value.size()));
    lv2_atom_forge_pop(&forge, &obj);
    lv2_atom_forge_pop(&forge, &seq);
  }

  /// One block of `input`; the worker runs after it and its answers are delivered.
  void run(const float* input, std::vector<float>* out_left = nullptr, std::vector<float>* out_right = nullptr) {
    std::copy_n(input, kBlock, in_.begin());
    auto* n = reinterpret_cast<LV2_Atom_Sequence*>(notify_.data());
    n->atom.size = sizeof notify_ - sizeof(LV2_Atom);
    lilv_instance_run(instance_, kBlock);
    clear_control();
    if (out_left) out_left->insert(out_left->end(), left_.begin(), left_.end());
    if (out_right) out_right->insert(out_right->end(), right_.begin(), right_.end());
    const auto* worker = static_cast<const LV2_Worker_Interface*>(lilv_instance_get_extension_data(instance_, LV2_WORKER__interface));
    auto jobs = std::move(jobs_);
    jobs_.clear();
    std::vector<std::vector<std::uint8_t>> answers;
    for (auto& j : jobs)
      worker->work(
          lilv_instance_get_handle(instance_),
          [](LV2_Worker_Respond_Handle h, std::uint32_t size, const void* data) {
            const auto* b = static_cast<const std::uint8_t*>(data);
            static_cast<std::vector<std::vector<std::uint8_t>>*>(h)->emplace_back(b, b + size);
            return LV2_WORKER_SUCCESS;
          },
          &answers, static_cast<std::uint32_t>(j.size()), j.data());
    for (auto& a : answers)
      worker->work_response(lilv_instance_get_handle(instance_), static_cast<std::uint32_t>(a.size()), a.data());
  }

  /// Saves the state (control inputs and the plugin's own) into `dir` as jalv
  /// does: a scratch directory of the session's own, links and copies in `dir`.
  /// (Without a scratch directory lilv 0.24 treats every file as scratch and
  /// moves it, deleting the SOFA file the state names: never pass null.)
  void save(const fs::path& dir, const fs::path& scratch) {
    fs::create_directories(scratch);
    LilvState* state = lilv_state_new_from_instance(
        plugin_, instance_, &urids_.map, scratch.c_str(), dir.c_str(), dir.c_str(), dir.c_str(),
        [](const char* symbol, void* user, std::uint32_t* size, std::uint32_t* type) -> const void* {
          auto* s = static_cast<Session*>(user);
          const auto it = s->symbols_.find(symbol);
          const LilvPort* port = lilv_plugin_get_port_by_index(s->plugin_, it->second);
          LilvNode* input = lilv_new_uri(s->world_, LV2_CORE__InputPort);
          LilvNode* control = lilv_new_uri(s->world_, LV2_CORE__ControlPort);
          const bool wanted = lilv_port_is_a(s->plugin_, port, input) && lilv_port_is_a(s->plugin_, port, control);
          lilv_node_free(input);
          lilv_node_free(control);
          if (!wanted) return nullptr;
          *size = sizeof(float);
          *type = s->map(LV2_ATOM__Float);
          return &s->values_[it->second];
        },
        this, LV2_STATE_IS_POD | LV2_STATE_IS_PORTABLE, features_.data());
    ASSERT_NE(state, nullptr);
    ASSERT_EQ(lilv_state_save(world_, &urids_.map, &urids_.unmap, state, nullptr, dir.c_str(), "state.ttl"), 0);
    lilv_state_free(state);
  }

  /// Applies the bundle's preset `uri` as jalv does (lilv_state_new_from_world).
  void apply_preset(const std::string& uri) {
    LilvNode* node = lilv_new_uri(world_, uri.c_str());
    lilv_world_load_resource(world_, node);
    LilvState* state = lilv_state_new_from_world(world_, &urids_.map, node);
    lilv_node_free(node);
    ASSERT_NE(state, nullptr) << "lilv could not read the preset " << uri;
    apply(state);
  }

  /// Restores the state saved in `dir` (this session's own world and map).
  void restore(const fs::path& dir) {
    LilvState* state = lilv_state_new_from_file(world_, &urids_.map, nullptr, (dir / "state.ttl").c_str());
    ASSERT_NE(state, nullptr) << "lilv could not read " << dir / "state.ttl";
    apply(state);
  }

 private:
  void apply(LilvState* state) {
    lilv_state_restore(
        state, instance_,
        [](const char* symbol, void* user, const void* value, std::uint32_t size, std::uint32_t type) {
          auto* s = static_cast<Session*>(user);
          if (type == s->map(LV2_ATOM__Float) && size == sizeof(float)) std::memcpy(&s->control(symbol), value, size);
        },
        this, 0, features_.data());
    lilv_state_free(state);
  }

  LV2_URID map(const char* uri) { return urids_.map.map(urids_.map.handle, uri); }
  void clear_control() {
    auto* seq = reinterpret_cast<LV2_Atom_Sequence*>(control_.data());
    seq->atom.type = map(LV2_ATOM__Sequence);
    seq->atom.size = sizeof(LV2_Atom_Sequence_Body);
    seq->body.unit = seq->body.pad = 0;
  }

  LilvWorld* world_;
  const LilvPlugin* plugin_ = nullptr;
  LilvInstance* instance_ = nullptr;
  Urids urids_;
  LV2_Worker_Schedule schedule_{};
  LV2_Feature map_feature_{}, unmap_feature_{}, schedule_feature_{};
  std::array<const LV2_Feature*, 4> features_{};
  std::vector<std::vector<std::uint8_t>> jobs_;
  std::map<std::string, std::uint32_t> symbols_;
  std::vector<float> values_;
  std::array<float, kBlock> in_{}, left_{}, right_{};
  std::array<std::uint64_t, 1024> control_{}, notify_{};
};

std::vector<float> noise(std::size_t n) {
  std::mt19937 rng(17);
  std::normal_distribution<float> d(0.0f, 0.1f);
  std::vector<float> v(n);
  for (auto& x : v) x = d(rng);
  return v;
}

}  // namespace

TEST(Lv2LilvState, ASavedSessionRestoredInAnotherGivesTheSameOutput) {
  const fs::path work = fs::path(EARSHOT_WORK) / "lilv_state";
  fs::remove_all(work);
  fs::create_directories(work);
  const fs::path sofa = work / "set.sofa";
  const std::string make = std::string("/usr/bin/python3 ") + EARSHOT_MAKE_SOFA + " --out '" + sofa.string() +
                           "' --length 64 --grid fibonacci:300";
  ASSERT_EQ(std::system(make.c_str()), 0) << make;
  const auto in = noise(kBlock * 60);

  std::vector<float> l1, r1;
  {
    Session first;
    ASSERT_TRUE(first.ok());
    first.control("azimuth") = 50.0f;
    first.control("elevation") = 10.0f;
    first.control("distance") = 2.0f;
    first.control("room") = 5.0f;  // living-room
    first.control("reverb_send") = -6.0f;
    first.control("yaw_offset") = 20.0f;
    const std::vector<float> silence(kBlock, 0.0f);
    first.patch_set(std::string(kUri) + "#tracker", "osc:9321", LV2_ATOM__String);
    first.run(silence.data());
    first.patch_set(std::string(kUri) + "#sofa", sofa.string(), LV2_ATOM__Path);
    first.run(silence.data());  // the set arrives through the worker, after this block
    // The switch warms the new panner and crossfades (1024 frames): let it
    // finish on silence, so both sessions' panners have heard only silence.
    for (int i = 0; i < 5; ++i) first.run(silence.data());
    for (std::size_t b = 0; b < in.size() / kBlock; ++b) first.run(in.data() + b * kBlock, &l1, &r1);
    first.save(work / "saved", work / "scratch");
  }
  ASSERT_TRUE(fs::exists(work / "saved" / "state.ttl"));

  std::vector<float> l2, r2;
  {
    Session second;
    ASSERT_TRUE(second.ok());
    second.restore(work / "saved");
    EXPECT_EQ(second.control("azimuth"), 50.0f);
    EXPECT_EQ(second.control("room"), 5.0f);
    // A fresh instance with the state: its first block meets the same FIFO.
    const std::vector<float> silence(kBlock, 0.0f);
    second.run(silence.data());
    for (std::size_t b = 0; b < in.size() / kBlock; ++b) second.run(in.data() + b * kBlock, &l2, &r2);
  }
  ASSERT_EQ(l1.size(), l2.size());
  double energy = 0;
  for (float x : l1) energy += double(x) * x;
  EXPECT_GT(energy, 1.0);
  EXPECT_EQ(l1, l2);
  EXPECT_EQ(r1, r2);

  // And a session that never got the set renders something else (the test can fail).
  std::vector<float> l3, r3;
  {
    Session plain;
    ASSERT_TRUE(plain.ok());
    plain.control("azimuth") = 50.0f;
    plain.control("elevation") = 10.0f;
    plain.control("distance") = 2.0f;
    plain.control("room") = 5.0f;
    plain.control("reverb_send") = -6.0f;
    plain.control("yaw_offset") = 20.0f;
    const std::vector<float> silence(kBlock, 0.0f);
    plain.run(silence.data());
    for (std::size_t b = 0; b < in.size() / kBlock; ++b) plain.run(in.data() + b * kBlock, &l3, &r3);
  }
  EXPECT_NE(l1, l3);
}

// What lv2lint checks of the bundle (lv2lint is not a Debian package, so it
// is run outside this suite; these are its checks, through lilv, so a
// regression fails here): a maintainer's name, address and home page, a
// project with a name, a stable version (even minor and micro numbers, the
// minor not 0), a short description; each control port named, its default
// within its range, integer and toggled ports with integer numbers, toggles
// 0 or 1; a bypass port (lv2:enabled) that defaults to on; the presets.
TEST(Lv2Lilv, TheMetadataLv2lintChecks) {
  LilvWorld* world = lilv_world_new();
  LilvNode* bundle = lilv_new_file_uri(world, nullptr, (std::string(EARSHOT_LV2_BUNDLE) + "/").c_str());
  lilv_world_load_bundle(world, bundle);
  lilv_node_free(bundle);
  LilvNode* uri = lilv_new_uri(world, kUri);
  const LilvPlugin* plugin = lilv_plugins_get_by_uri(lilv_world_get_all_plugins(world), uri);
  ASSERT_NE(plugin, nullptr);
  EXPECT_TRUE(lilv_plugin_verify(plugin));
  for (LilvNode* n : {lilv_plugin_get_author_name(plugin), lilv_plugin_get_author_email(plugin),
                      lilv_plugin_get_author_homepage(plugin)}) {
    EXPECT_NE(n, nullptr) << "a doap:maintainer's foaf:name, foaf:mbox and foaf:homepage";
    lilv_node_free(n);
  }
  LilvNode* project = lilv_plugin_get_project(plugin);
  ASSERT_NE(project, nullptr);
  LilvNode* doap_name = lilv_new_uri(world, "http://usefulinc.com/ns/doap#name");
  LilvNode* project_name = lilv_world_get(world, project, doap_name, nullptr);
  EXPECT_TRUE(project_name && lilv_node_is_string(project_name));
  lilv_node_free(project_name);
  lilv_node_free(project);
  auto get_int = [&](const char* property) {
    LilvNode* p = lilv_new_uri(world, property);
    LilvNodes* v = lilv_plugin_get_value(plugin, p);
    lilv_node_free(p);
    const int out = v && lilv_node_is_int(lilv_nodes_get_first(v)) ? lilv_node_as_int(lilv_nodes_get_first(v)) : -1;
    lilv_nodes_free(v);
    return out;
  };
  const int minor = get_int(LV2_CORE__minorVersion), micro = get_int(LV2_CORE__microVersion);
  EXPECT_TRUE(minor > 0 && minor % 2 == 0) << "lv2:minorVersion " << minor << " is not a stable (even, non-zero) one";
  EXPECT_TRUE(micro >= 0 && micro % 2 == 0) << "lv2:microVersion " << micro;
  LilvNode* shortdesc = lilv_new_uri(world, "http://usefulinc.com/ns/doap#shortdesc");
  LilvNodes* sd = lilv_plugin_get_value(plugin, shortdesc);
  EXPECT_TRUE(sd && lilv_node_is_string(lilv_nodes_get_first(sd)));
  lilv_nodes_free(sd);

  LilvNode* control = lilv_new_uri(world, LV2_CORE__ControlPort);
  LilvNode* input = lilv_new_uri(world, LV2_CORE__InputPort);
  LilvNode* integer = lilv_new_uri(world, LV2_CORE__integer);
  LilvNode* toggled = lilv_new_uri(world, LV2_CORE__toggled);
  LilvNode* enabled = lilv_new_uri(world, LV2_CORE__enabled);
  LilvNode* dflt = lilv_new_uri(world, LV2_CORE__default);
  LilvNode* minimum = lilv_new_uri(world, LV2_CORE__minimum);
  LilvNode* maximum = lilv_new_uri(world, LV2_CORE__maximum);
  LilvNode* designation_uri = lilv_new_uri(world, LV2_CORE__designation);
  bool found_enabled = false;
  for (std::uint32_t i = 0; i < lilv_plugin_get_num_ports(plugin); ++i) {
    const LilvPort* port = lilv_plugin_get_port_by_index(plugin, i);
    const std::string symbol = lilv_node_as_string(lilv_port_get_symbol(plugin, port));
    LilvNode* name = lilv_port_get_name(plugin, port);
    EXPECT_NE(name, nullptr) << symbol;
    lilv_node_free(name);
    if (!lilv_port_is_a(plugin, port, control)) continue;
    LilvNode *d = nullptr, *lo = nullptr, *hi = nullptr;
    lilv_port_get_range(plugin, port, &d, &lo, &hi);
    const bool in = lilv_port_is_a(plugin, port, input);
    const bool whole = lilv_port_has_property(plugin, port, integer) || lilv_port_has_property(plugin, port, toggled);
    if (in) {
      ASSERT_TRUE(d && lo && hi) << symbol << ": default, minimum and maximum";
      EXPECT_LE(lilv_node_as_float(lo), lilv_node_as_float(d)) << symbol;
      EXPECT_LE(lilv_node_as_float(d), lilv_node_as_float(hi)) << symbol;
    }
    if (whole) {
      for (const LilvNode* n : {in ? d : lo, lo, hi}) {
        if (n) {
          EXPECT_TRUE(lilv_node_is_int(n)) << symbol << ": " << lilv_node_as_string(n) << " is not an integer";
        }
      }
    }
    if (in && lilv_port_has_property(plugin, port, toggled)) {
      EXPECT_TRUE(lilv_node_as_int(d) == 0 || lilv_node_as_int(d) == 1) << symbol;
    }
    LilvNode* designation = lilv_port_get(plugin, port, designation_uri);
    if (designation && lilv_node_equals(designation, enabled)) {
      found_enabled = true;
      EXPECT_EQ(symbol, "enabled");
      EXPECT_EQ(lilv_node_as_int(d), 1) << "bypass off by default";
    }
    lilv_node_free(designation);
    lilv_node_free(d);
    lilv_node_free(lo);
    lilv_node_free(hi);
  }
  EXPECT_TRUE(found_enabled) << "no port designated lv2:enabled";

  LilvNode* preset_class = lilv_new_uri(world, "http://lv2plug.in/ns/ext/presets#Preset");
  LilvNodes* presets = lilv_plugin_get_related(plugin, preset_class);
  EXPECT_EQ(presets ? lilv_nodes_size(presets) : 0u, 4u);
  lilv_nodes_free(presets);
  for (LilvNode* n : {doap_name, shortdesc, control, input, integer, toggled, enabled, dflt, minimum, maximum, designation_uri,
                      preset_class, uri})
    lilv_node_free(n);
  lilv_world_free(world);
}

// The presets as a host applies them (lilv, as jalv's preset menu): the
// ports, and the tracker spec and send list in their state.
TEST(Lv2Lilv, PresetsSetThePortsAndTheTrackersSpec) {
  const fs::path work = fs::path(EARSHOT_WORK) / "presets";
  fs::remove_all(work);
  Session s;
  ASSERT_TRUE(s.ok());
  s.control("azimuth") = 45;
  s.apply_preset(std::string(kUri) + "#preset-webcam-tag");
  EXPECT_EQ(s.control("tracking"), 1.0f);
  EXPECT_EQ(s.control("azimuth"), 0.0f);
  s.save(work / "webcam", work / "scratch");
  std::ifstream f(work / "webcam" / "state.ttl");
  const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("webcam,beacon=apriltag,size_mm=50"), std::string::npos) << text;
  EXPECT_NE(text.find("osc:127.0.0.1:9001,format=sparta"), std::string::npos) << text;

  s.apply_preset(std::string(kUri) + "#preset-osc-head-tracking");
  EXPECT_EQ(s.control("tracking"), 1.0f);
  EXPECT_EQ(s.control("tracker_source"), 3.0f);
  EXPECT_EQ(s.control("osc_port"), 9000.0f);
  s.apply_preset(std::string(kUri) + "#preset-straight-ahead");
  EXPECT_EQ(s.control("tracking"), 0.0f);
  EXPECT_EQ(s.control("enabled"), 1.0f);
  s.save(work / "straight", work / "scratch2");
  std::ifstream g(work / "straight" / "state.ttl");
  const std::string plain((std::istreambuf_iterator<char>(g)), std::istreambuf_iterator<char>());
  EXPECT_EQ(plain.find("webcam"), std::string::npos) << "the webcam spec outlived the preset that clears it";
}
