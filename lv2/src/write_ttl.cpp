// Writes the bundle's turtle (manifest.ttl, earshot.ttl, presets.ttl and,
// for the Ambisonic decoders, ambi.ttl) at
// build time, from the same tables the code uses: the room presets and
// distance models become the enumeration ports' scale points, so the turtle
// cannot drift from the binary. Integer and toggled ports get integer
// numbers (what lv2lint asks for; lilv reads a boolean literal as 0, so
// toggles are 0 and 1, not false and true). Usage:
// earshot_lv2_ttl BUNDLE_DIR LIBRARY_FILE_NAME
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <utility>
#include <vector>

#include "earshot/audio/room_presets.hpp"
#include "earshot/host/distance_models.hpp"
#include "ambi_plugin.hpp"
#include "uris.hpp"

namespace {

constexpr const char* kPrefixes = R"(@prefix atom:  <http://lv2plug.in/ns/ext/atom#> .
@prefix doap:  <http://usefulinc.com/ns/doap#> .
@prefix foaf:  <http://xmlns.com/foaf/0.1/> .
@prefix log:   <http://lv2plug.in/ns/ext/log#> .
@prefix lv2:   <http://lv2plug.in/ns/lv2core#> .
@prefix patch: <http://lv2plug.in/ns/ext/patch#> .
@prefix pprops: <http://lv2plug.in/ns/ext/port-props#> .
@prefix pset:  <http://lv2plug.in/ns/ext/presets#> .
@prefix rdf:   <http://www.w3.org/1999/02/22-rdf-syntax-ns#> .
@prefix rdfs:  <http://www.w3.org/2000/01/rdf-schema#> .
@prefix state: <http://lv2plug.in/ns/ext/state#> .
@prefix units: <http://lv2plug.in/ns/extensions/units#> .
@prefix urid:  <http://lv2plug.in/ns/ext/urid#> .
@prefix work:  <http://lv2plug.in/ns/ext/worker#> .
)";

struct Control {
  const char* symbol;
  const char* name;
  double def, min, max;
  const char* unit;  // units: term or nullptr
  const char* extra;  // more properties, or ""
  const char* comment = nullptr;  // rdfs:comment, or nullptr
};

/// A number as the turtle should carry it: an integer literal for integer
/// and toggled ports, a decimal otherwise.
std::string number(double v, bool whole) {
  if (whole) return std::to_string(static_cast<long long>(std::llround(v)));
  return std::to_string(v);
}

void control_port(std::ostream& o, int index, const Control& c, bool output = false) {
  const std::string extra = c.extra;
  const bool whole = extra.find("lv2:integer") != std::string::npos || extra.find("lv2:toggled") != std::string::npos;
  o << "\t\t[\n\t\t\ta lv2:" << (output ? "OutputPort" : "InputPort") << " , lv2:ControlPort ;\n"
    << "\t\t\tlv2:index " << index << " ;\n\t\t\tlv2:symbol \"" << c.symbol << "\" ;\n"
    << "\t\t\tlv2:name \"" << c.name << "\" ;\n";
  if (c.comment) o << "\t\t\trdfs:comment \"" << c.comment << "\" ;\n";
  if (!output) o << "\t\t\tlv2:default " << number(c.def, whole) << " ;\n";
  o << "\t\t\tlv2:minimum " << number(c.min, whole) << " ;\n\t\t\tlv2:maximum " << number(c.max, whole) << " ;\n";
  if (c.unit) o << "\t\t\tunits:unit units:" << c.unit << " ;\n";
  o << c.extra << "\t\t]";
}

// Who maintains the bundle (lv2lint warns without a name, an address and a
// home page): the project's maintainers, at the address its commits carry.
// On the doap:Project (doap:maintainer's domain), which lilv reads for a
// plugin that has none of its own.
// The project has no web page of its own yet: its URN stands in.
constexpr const char* kMaintainer =
    "[\n\t\ta foaf:Person ;\n\t\tfoaf:name \"Earshot maintainers\" ;\n"
    "\t\tfoaf:mbox <mailto:maintainers@users.noreply.h-seed-88af6bed.example> ;\n"
    "\t\tfoaf:homepage <" EARSHOT_LV2_PROJECT ">\n\t]";

/// One preset: a label, port values, and the state's tracker spec and send list.
struct Preset {
  const char* id;  // the URI's fragment
  const char* label;
  const char* comment;
  std::vector<std::pair<const char*, double>> ports;
  const char* tracker;
  const char* send;
};

// Port properties both plugins use.
const std::string kToggle = "\t\t\tlv2:portProperty lv2:toggled ;\n";
const std::string kSources =
    "\t\t\tlv2:portProperty lv2:integer , lv2:enumeration ;\n\t\t\tlv2:scalePoint [ rdfs:label \"wiimote\" ; "
    "rdf:value 0 ] , [ rdfs:label \"sim\" ; rdf:value 1 ] , [ rdfs:label \"opentrack\" ; rdf:value 2 ] , "
    "[ rdfs:label \"osc\" ; rdf:value 3 ] ;\n";
const std::string kTrigger = "\t\t\tlv2:portProperty lv2:toggled , pprops:trigger ;\n";
const std::string kLatency = "\t\t\tlv2:designation lv2:latency ;\n\t\t\tlv2:portProperty lv2:reportsLatency , "
                             "lv2:integer ;\n";

/// The tracker spec parameter (a patch:writable string) under `uri`.
void tracker_parameter(std::ostream& o, const std::string& uri) {
  o << "<" << uri << ">\n\ta lv2:Parameter ;\n\trdfs:label \"Tracker spec\" ;\n"
       "\trdfs:comment \"A full tracker spec (wiimote, sim, replay:FILE, opentrack[:PORT], osc[:PORT], with @ADDR to "
       "listen beyond 127.0.0.1); empty: the tracker_source port decides.\" ;\n"
       "\trdfs:range atom:String .\n\n";
}

/// The ports after the head-tracking controls: latency and the head's
/// yaw, pitch and roll as outputs. `last`: end the port list.
void latency_and_head_ports(std::ostream& o, int& index, bool last) {
  control_port(o, index++, {"latency", "Latency", 0, 0, 8192, "frame", kLatency.c_str()}, true);
  o << " ,\n";
  control_port(o, index++, {"head_yaw", "Head yaw", 0, -180, 180, "degree", ""}, true);
  o << " ,\n";
  control_port(o, index++, {"head_pitch", "Head pitch", 0, -90, 90, "degree", ""}, true);
  o << " ,\n";
  control_port(o, index++, {"head_roll", "Head roll", 0, -180, 180, "degree", ""}, true);
  o << (last ? " .\n\n" : " ,\n");
}

std::vector<Preset> presets() {
  // Every preset sets every control a person would set, so one applied
  // after another leaves nothing of the first behind.
  const std::vector<std::pair<const char*, double>> base{
      {"azimuth", 0},       {"elevation", 0},   {"distance", 1},       {"gain", 0},         {"distance_model", 2},
      {"room", 0},          {"reverb_send", -12}, {"yaw_offset", 0},   {"pitch_offset", 0}, {"roll_offset", 0},
      {"enabled", 1},       {"invert_yaw", 0},  {"invert_pitch", 0},   {"invert_roll", 0},  {"rotation_order", 0},
      {"osc_port", 9000},   {"opentrack_port", 4242}};
  auto with = [&](std::vector<std::pair<const char*, double>> more) {
    auto all = base;
    all.insert(all.end(), more.begin(), more.end());
    return all;
  };
  return {
      {"straight-ahead", "Straight ahead",
       "The source 1 m straight ahead of a head that does not move: no tracking, no room.",
       with({{"tracking", 0}, {"tracker_source", 0}}), "", ""},
      {"osc-head-tracking", "OSC head tracking",
       "The head from OSC on port 9000 of 127.0.0.1: Earshot's, SPARTA's and the IEM SceneRotator's addresses "
       "(a head tracker set up for SPARTA or IEM drives it unchanged).",
       with({{"tracking", 1}, {"tracker_source", 3}}), "", ""},
      {"opentrack-head-tracking", "opentrack head tracking",
       "The head from opentrack's UDP over network output on port 4242 of 127.0.0.1.",
       with({{"tracking", 1}, {"tracker_source", 2}}), "", ""},
      {"webcam-tag", "Webcam tag",
       "The head from the first webcam watching a printed AprilTag (tag36h11 whose black square measures 50 mm), "
       "its poses also sent on to SPARTA's plug-ins on port 9001.",
       with({{"tracking", 1}, {"tracker_source", 0}}), "webcam,beacon=apriltag,size_mm=50",
       "osc:127.0.0.1:9001,format=sparta"},
  };
}

}  // namespace

namespace {

/// The Ambisonic decoders (ambi_plugin.hpp): one plugin per order in
/// ambi.ttl, listed in the manifest. Ports: the (N+1)^2 inputs in ACN order,
/// then ambi::Port's.
bool write_ambi_ttl(const std::string& dir, const std::string& library, std::ostream& manifest) {
  namespace ambi = earshot::lv2::ambi;
  std::ofstream o(dir + "/ambi.ttl");
  o << kPrefixes << "\n";
  tracker_parameter(o, ambi::kTrackerParameter);
  for (int order = 1; order <= ambi::kOrders; ++order) {
    const std::string uri = EARSHOT_LV2_AMBI_URI_PREFIX + std::to_string(order);
    const int channels = (order + 1) * (order + 1);
    manifest << "\n<" << uri << ">\n\ta lv2:Plugin ;\n\tlv2:binary <" << library << "> ;\n\trdfs:seeAlso <ambi.ttl> .\n";
    o << "<" << uri << ">\n\ta lv2:Plugin , lv2:SpatialPlugin ;\n"
      << "\tdoap:name \"Earshot Ambisonic binaural decoder, order " << order << "\" ;\n"
      << "\tdoap:license <https://opensource.org/licenses/MIT> ;\n\tlv2:minorVersion 1 ;\n\tlv2:microVersion 0 ;\n"
      << "\trdfs:comment \"An order-" << order << " Ambisonic signal (" << channels
      << " inputs, ambiX: ACN channel order, SN3D; x, y, z = ahead, left, up) to two ears for a head-tracked "
         "listener: the field turned by the head (SH rotation, glided across each block), then a MagLS binaural "
         "decoder designed from MIT KEMAR. The head from a Wii Remote, opentrack, OSC or the simulator, shared with "
         "every Earshot plugin in the process.\" ;\n"
      << "\tlv2:optionalFeature lv2:hardRTCapable , urid:map , work:schedule , log:log ;\n"
      << "\tlv2:extensionData work:interface , state:interface ;\n"
      << "\tpatch:writable <" << ambi::kTrackerParameter << "> ;\n\tlv2:port\n";
    int index = 0;
    for (int c = 0; c < channels; ++c, ++index) {
      const int l = static_cast<int>(std::sqrt(static_cast<double>(c)) + 1e-9), m = c - l * l - l;
      o << "\t\t[\n\t\t\ta lv2:InputPort , lv2:AudioPort ;\n\t\t\tlv2:index " << index << " ;\n"
        << "\t\t\tlv2:symbol \"acn" << c << "\" ;\n\t\t\tlv2:name \"ACN " << c << " (l " << l << ", m " << m << ")\" ;\n\t\t] ,\n";
    }
    const auto audio_out = [&](const char* symbol, const char* name) {
      o << "\t\t[\n\t\t\ta lv2:OutputPort , lv2:AudioPort ;\n\t\t\tlv2:index " << index << " ;\n"
        << "\t\t\tlv2:symbol \"" << symbol << "\" ;\n\t\t\tlv2:name \"" << name << "\" ;\n\t\t] ,\n";
      ++index;
    };
    const auto atom = [&](bool input, const char* symbol, const char* name) {
      o << "\t\t[\n\t\t\ta lv2:" << (input ? "InputPort" : "OutputPort")
        << " , atom:AtomPort ;\n\t\t\tatom:bufferType atom:Sequence ;\n"
        << "\t\t\tatom:supports patch:Message ;\n\t\t\tlv2:designation lv2:control ;\n"
        << "\t\t\tlv2:portProperty lv2:connectionOptional ;\n\t\t\tlv2:index " << index << " ;\n"
        << "\t\t\tlv2:symbol \"" << symbol << "\" ;\n\t\t\tlv2:name \"" << name << "\" ;\n\t\t] ,\n";
      ++index;
    };
    audio_out("out_left", "Left");
    audio_out("out_right", "Right");
    atom(true, "control", "Control");
    atom(false, "notify", "Notify");
    const Control inputs[] = {
        {"tracking", "Head tracking", 0, 0, 1, nullptr, kToggle.c_str()},
        {"tracker_source", "Tracker", 0, 0, 3, nullptr, kSources.c_str()},
        {"recenter", "Recenter", 0, 0, 1, nullptr, kTrigger.c_str()},
        {"yaw_offset", "Yaw offset (positive left)", 0, -180, 180, "degree", ""},
        {"pitch_offset", "Pitch offset (positive up)", 0, -90, 90, "degree", ""},
        {"roll_offset", "Roll offset (positive right)", 0, -180, 180, "degree", ""},
    };
    for (const auto& c : inputs) {
      control_port(o, index++, c);
      o << " ,\n";
    }
    latency_and_head_ports(o, index, true);
    if (index != channels + static_cast<int>(ambi::kPortsAfterInputs)) {
      std::cerr << "earshot_lv2_ttl: the Ambisonic ports written do not match ambi_plugin.hpp\n";
      return false;
    }
  }
  return static_cast<bool>(o);
}

}  // namespace

namespace {

/// The panner's presets (presets()) into presets.ttl, each listed in the manifest.
bool write_presets_ttl(const std::string& dir, std::ostream& manifest) {
  std::ofstream pset(dir + "/presets.ttl");
  pset << kPrefixes << "\n";
  for (const Preset& p : presets()) {
    const std::string uri = std::string(EARSHOT_LV2_URI "#preset-") + p.id;
    manifest << "\n<" << uri << ">\n\ta pset:Preset ;\n\tlv2:appliesTo <" EARSHOT_LV2_URI "> ;\n"
             << "\trdfs:seeAlso <presets.ttl> .\n";
    pset << "<" << uri << ">\n\ta pset:Preset ;\n\tlv2:appliesTo <" EARSHOT_LV2_URI "> ;\n\trdfs:label \"" << p.label
         << "\" ;\n\trdfs:comment \"" << p.comment << "\" ;\n\tlv2:port";
    for (std::size_t i = 0; i < p.ports.size(); ++i)
      pset << (i ? " ,\n\t\t" : "\n\t\t") << "[ lv2:symbol \"" << p.ports[i].first << "\" ; pset:value "
           << std::to_string(p.ports[i].second) << " ]";
    pset << " ;\n\tstate:state [\n\t\t<" EARSHOT_LV2_TRACKER "> \"" << p.tracker << "\" ;\n\t\t<" EARSHOT_LV2_SEND
         << "> \"" << p.send << "\"\n\t] .\n\n";
  }
  return static_cast<bool>(pset);
}

/// The panner's parameters, project and plugin, up to its five fixed ports
/// (audio in, left, right, control and notify).
void panner_header(std::ostream& o) {
  o << kPrefixes << "\n";
  o << "<" EARSHOT_LV2_SOFA ">\n\ta lv2:Parameter ;\n\trdfs:label \"HRTF set (SOFA file)\" ;\n"
       "\trdfs:comment \"A SimpleFreeFieldHRIR SOFA file; the default is the MIT KEMAR set libmysofa ships.\" ;\n"
       "\trdfs:range atom:Path .\n\n";
  tracker_parameter(o, EARSHOT_LV2_TRACKER);
  o << "<" EARSHOT_LV2_SEND ">\n\ta lv2:Parameter ;\n\trdfs:label \"Send poses to\" ;\n"
       "\trdfs:comment \"Where the tracker also sends its poses, ';' between several: osc[:HOST][:PORT]"
       "[,format=earshot|sparta|iem|iem-ypr][,rate=HZ] or opentrack[:HOST][:PORT][,rate=HZ]; 127.0.0.1 unless a host "
       "is named. Instances that share a tracker share this.\" ;\n"
       "\trdfs:range atom:String .\n\n";
  o << "<" EARSHOT_LV2_PROJECT ">\n\ta doap:Project ;\n\tdoap:name \"Earshot\" ;\n"
       "\tdoap:shortdesc \"Head-tracked binaural audio\" ;\n\tdoap:maintainer " << kMaintainer << " .\n\n";
  o << "<" EARSHOT_LV2_URI ">\n\ta lv2:Plugin , lv2:SpatialPlugin ;\n"
       "\tdoap:name \"Earshot binaural panner\" ;\n"
       "\tdoap:shortdesc \"A head-tracked binaural panner\" ;\n"
       "\tlv2:project <" EARSHOT_LV2_PROJECT "> ;\n"  // its doap:maintainer is the plugin's (lilv looks there)
       "\tdoap:license <https://opensource.org/licenses/MIT> ;\n"
       "\tlv2:minorVersion 2 ;\n\tlv2:microVersion 0 ;\n"
       "\trdfs:comment \"A mono source placed around a head-tracked listener: HRTF from any SOFA set with "
       "fractional ITD, OpenAL's distance models, a room reverb; the head from a Wii Remote, opentrack, OSC or the "
       "simulator, shared by every instance in the process.\" ;\n"
       "\tlv2:optionalFeature lv2:hardRTCapable , urid:map , work:schedule , log:log ;\n"
       "\tlv2:extensionData work:interface , state:interface ;\n"
       "\tpatch:writable <" EARSHOT_LV2_SOFA "> , <" EARSHOT_LV2_TRACKER "> , <" EARSHOT_LV2_SEND "> ;\n"
       "\tlv2:port\n";
  o << "\t\t[\n\t\t\ta lv2:InputPort , lv2:AudioPort ;\n\t\t\tlv2:index 0 ;\n\t\t\tlv2:symbol \"in\" ;\n"
       "\t\t\tlv2:name \"In\" ;\n\t\t] , [\n\t\t\ta lv2:OutputPort , lv2:AudioPort ;\n\t\t\tlv2:index 1 ;\n"
       "\t\t\tlv2:symbol \"out_left\" ;\n\t\t\tlv2:name \"Left\" ;\n\t\t] , [\n"
       "\t\t\ta lv2:OutputPort , lv2:AudioPort ;\n\t\t\tlv2:index 2 ;\n\t\t\tlv2:symbol \"out_right\" ;\n"
       "\t\t\tlv2:name \"Right\" ;\n\t\t] , [\n"
       "\t\t\ta lv2:InputPort , atom:AtomPort ;\n\t\t\tatom:bufferType atom:Sequence ;\n"
       "\t\t\tatom:supports patch:Message ;\n\t\t\tlv2:designation lv2:control ;\n"
       "\t\t\tlv2:portProperty lv2:connectionOptional ;\n\t\t\tlv2:index 3 ;\n\t\t\tlv2:symbol \"control\" ;\n"
       "\t\t\tlv2:name \"Control\" ;\n\t\t] , [\n"
       "\t\t\ta lv2:OutputPort , atom:AtomPort ;\n\t\t\tatom:bufferType atom:Sequence ;\n"
       "\t\t\tatom:supports patch:Message ;\n\t\t\tlv2:designation lv2:control ;\n"
       "\t\t\tlv2:portProperty lv2:connectionOptional ;\n\t\t\tlv2:index 4 ;\n\t\t\tlv2:symbol \"notify\" ;\n"
       "\t\t\tlv2:name \"Notify\" ;\n\t\t] ,\n";
}

/// The distance models' and the room presets' scale points (port properties).
std::string distance_model_points() {
  std::string models;
  for (std::size_t i = 0; i < earshot::host::kDistanceModels.size(); ++i)
    models += std::string(i ? " , " : "\t\t\tlv2:scalePoint ") + "[ rdfs:label \"" +
              earshot::host::kDistanceModels[i].name + "\" ; rdf:value " + std::to_string(i) + " ]";
  models = "\t\t\tlv2:portProperty lv2:integer , lv2:enumeration ;\n" + models + " ;\n";
  return models;
}

std::string room_points() {
  std::string rooms = "\t\t\tlv2:portProperty lv2:integer , lv2:enumeration ;\n\t\t\tlv2:scalePoint [ rdfs:label "
                      "\"none\" ; rdf:value 0 ]";
  const auto presets = earshot::audio::room_presets();
  for (std::size_t i = 0; i < presets.size(); ++i)
    rooms += " , [ rdfs:label \"" + std::string(presets[i].name) + "\" ; rdf:value " + std::to_string(i + 1) + " ]";
  rooms += " ;\n";
  return rooms;
}

/// The panner's control ports from index 5 on; the appended ones last, in
/// the order of their minor versions.
void panner_controls(std::ostream& o) {
  const std::string models = distance_model_points(), rooms = room_points();
  const auto rooms_count = earshot::audio::room_presets().size();
  const std::string log_scale = "\t\t\tlv2:portProperty pprops:logarithmic ;\n";

  const Control inputs[] = {
      {"azimuth", "Azimuth (positive left)", 0, -180, 180, "degree", ""},
      {"elevation", "Elevation", 0, -90, 90, "degree", ""},
      {"distance", "Distance", 1, 0.1, 100, "m", log_scale.c_str()},
      {"gain", "Gain", 0, -60, 12, "db", ""},
      {"distance_model", "Distance model", 2, 0, 6, nullptr, models.c_str()},
      {"room", "Room", 0, 0, static_cast<double>(rooms_count), nullptr, rooms.c_str()},
      {"reverb_send", "Reverb send", -12, -60, 6, "db", ""},
      {"tracking", "Head tracking", 0, 0, 1, nullptr, kToggle.c_str()},
      {"tracker_source", "Tracker", 0, 0, 3, nullptr, kSources.c_str()},
      {"recenter", "Recenter", 0, 0, 1, nullptr, kTrigger.c_str()},
      {"yaw_offset", "Yaw offset (positive left)", 0, -180, 180, "degree", ""},
      {"pitch_offset", "Pitch offset (positive up)", 0, -90, 90, "degree", ""},
      {"roll_offset", "Roll offset (positive right)", 0, -180, 180, "degree", ""},
  };
  int index = 5;
  for (const auto& c : inputs) {
    control_port(o, index++, c);
    o << " ,\n";
  }
  latency_and_head_ports(o, index, false);
  // Appended in minor version 2: a host's saved session keeps its port numbers.
  const std::string enabled = "\t\t\tlv2:designation lv2:enabled ;\n\t\t\tlv2:portProperty lv2:toggled ;\n";
  const std::string order = "\t\t\tlv2:portProperty lv2:integer , lv2:enumeration ;\n\t\t\tlv2:scalePoint [ rdfs:label "
                            "\"yaw-pitch-roll\" ; rdf:value 0 ] , [ rdfs:label \"roll-pitch-yaw\" ; rdf:value 1 ] ;\n";
  const std::string port = "\t\t\tlv2:portProperty lv2:integer ;\n";
  const Control appended[] = {
      {"enabled", "Enabled", 1, 0, 1, nullptr, enabled.c_str(),
       "Off: the input, delayed by the latency, on both channels (a 21 ms fade either way)"},
      {"invert_yaw", "Invert yaw", 0, 0, 1, nullptr, kToggle.c_str(),
       "Turn the head's yaw the other way (as IEM SceneRotator's switch)"},
      {"invert_pitch", "Invert pitch", 0, 0, 1, nullptr, kToggle.c_str(), "Turn the head's pitch the other way"},
      {"invert_roll", "Invert roll", 0, 0, 1, nullptr, kToggle.c_str(), "Turn the head's roll the other way"},
      {"rotation_order", "Rotation order", 0, 0, 1, nullptr, order.c_str(),
       "The order the head's yaw, pitch and roll are put together in (as IEM SceneRotator's sequence)"},
      {"osc_port", "OSC port", 9000, 1, 65535, nullptr, port.c_str(),
       "UDP port of the osc tracker source, on 127.0.0.1 (SPARTA's default 9000)"},
      {"opentrack_port", "opentrack port", 4242, 1, 65535, nullptr, port.c_str(),
       "UDP port of the opentrack tracker source, on 127.0.0.1 (opentrack's default 4242)"},
  };
  for (std::size_t i = 0; i < std::size(appended); ++i) {
    control_port(o, index++, appended[i]);
    o << (i + 1 < std::size(appended) ? " ,\n" : " .\n");
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: earshot_lv2_ttl BUNDLE_DIR LIBRARY_FILE_NAME\n";
    return 2;
  }
  const std::string dir = argv[1], library = argv[2];
  std::ofstream manifest(dir + "/manifest.ttl");
  manifest << kPrefixes << "\n<" EARSHOT_LV2_URI ">\n\ta lv2:Plugin ;\n\tlv2:binary <" << library
           << "> ;\n\trdfs:seeAlso <earshot.ttl> .\n";
  const bool presets_ok = write_presets_ttl(dir, manifest);
  std::ofstream o(dir + "/earshot.ttl");
  panner_header(o);
  panner_controls(o);
  const bool ambi_ok = write_ambi_ttl(dir, library, manifest);
  if (!o || !manifest || !presets_ok || !ambi_ok) {
    std::cerr << "earshot_lv2_ttl: cannot write the turtle into " << dir << "\n";
    return 1;
  }
  return 0;
}
