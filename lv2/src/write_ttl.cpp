// Writes the bundle's turtle (manifest.ttl and earshot.ttl) at build time,
// from the same tables the code uses: the room presets and distance models
// become the enumeration ports' scale points, so the turtle cannot drift
// from the binary. Usage: earshot_lv2_ttl BUNDLE_DIR LIBRARY_FILE_NAME
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>

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
};

void control_port(std::ostream& o, int index, const Control& c, bool output = false) {
  o << "\t\t[\n\t\t\ta lv2:" << (output ? "OutputPort" : "InputPort") << " , lv2:ControlPort ;\n"
    << "\t\t\tlv2:index " << index << " ;\n\t\t\tlv2:symbol \"" << c.symbol << "\" ;\n"
    << "\t\t\tlv2:name \"" << c.name << "\" ;\n";
  if (!output) o << "\t\t\tlv2:default " << std::to_string(c.def) << " ;\n";
  o << "\t\t\tlv2:minimum " << std::to_string(c.min) << " ;\n\t\t\tlv2:maximum " << std::to_string(c.max) << " ;\n";
  if (c.unit) o << "\t\t\tunits:unit units:" << c.unit << " ;\n";
  o << c.extra << "\t\t]";
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
  o << "<" << ambi::kTrackerParameter << ">\n\ta lv2:Parameter ;\n\trdfs:label \"Tracker spec\" ;\n"
       "\trdfs:comment \"A full tracker spec (wiimote, sim, replay:FILE, opentrack[:PORT], osc[:PORT], with @ADDR to "
       "listen beyond 127.0.0.1); empty: the tracker_source port decides.\" ;\n"
       "\trdfs:range atom:String .\n\n";
  const std::string toggle = "\t\t\tlv2:portProperty lv2:toggled ;\n";
  const std::string sources =
      "\t\t\tlv2:portProperty lv2:integer , lv2:enumeration ;\n\t\t\tlv2:scalePoint [ rdfs:label \"wiimote\" ; "
      "rdf:value 0 ] , [ rdfs:label \"sim\" ; rdf:value 1 ] , [ rdfs:label \"opentrack\" ; rdf:value 2 ] , "
      "[ rdfs:label \"osc\" ; rdf:value 3 ] ;\n";
  const std::string trigger = "\t\t\tlv2:portProperty lv2:toggled , pprops:trigger ;\n";
  const std::string latency = "\t\t\tlv2:designation lv2:latency ;\n\t\t\tlv2:portProperty lv2:reportsLatency , "
                              "lv2:integer ;\n";
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
        {"tracking", "Head tracking", 0, 0, 1, nullptr, toggle.c_str()},
        {"tracker_source", "Tracker", 0, 0, 3, nullptr, sources.c_str()},
        {"recenter", "Recenter", 0, 0, 1, nullptr, trigger.c_str()},
        {"yaw_offset", "Yaw offset (positive left)", 0, -180, 180, "degree", ""},
        {"pitch_offset", "Pitch offset (positive up)", 0, -90, 90, "degree", ""},
        {"roll_offset", "Roll offset (positive right)", 0, -180, 180, "degree", ""},
    };
    for (const auto& c : inputs) {
      control_port(o, index++, c);
      o << " ,\n";
    }
    control_port(o, index++, {"latency", "Latency", 0, 0, 8192, "frame", latency.c_str()}, true);
    o << " ,\n";
    control_port(o, index++, {"head_yaw", "Head yaw", 0, -180, 180, "degree", ""}, true);
    o << " ,\n";
    control_port(o, index++, {"head_pitch", "Head pitch", 0, -90, 90, "degree", ""}, true);
    o << " ,\n";
    control_port(o, index++, {"head_roll", "Head roll", 0, -180, 180, "degree", ""}, true);
    o << " .\n\n";
    if (index != channels + static_cast<int>(ambi::kPortsAfterInputs)) {
      std::cerr << "earshot_lv2_ttl: the Ambisonic ports written do not match ambi_plugin.hpp\n";
      return false;
    }
  }
  return static_cast<bool>(o);
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

  std::ofstream o(dir + "/earshot.ttl");
  o << kPrefixes << "\n";
  o << "<" EARSHOT_LV2_SOFA ">\n\ta lv2:Parameter ;\n\trdfs:label \"HRTF set (SOFA file)\" ;\n"
       "\trdfs:comment \"A SimpleFreeFieldHRIR SOFA file; the default is the MIT KEMAR set libmysofa ships.\" ;\n"
       "\trdfs:range atom:Path .\n\n";
  o << "<" EARSHOT_LV2_TRACKER ">\n\ta lv2:Parameter ;\n\trdfs:label \"Tracker spec\" ;\n"
       "\trdfs:comment \"A full tracker spec (wiimote, sim, replay:FILE, opentrack[:PORT], osc[:PORT], with @ADDR to "
       "listen beyond 127.0.0.1); empty: the tracker_source port decides.\" ;\n"
       "\trdfs:range atom:String .\n\n";
  o << "<" EARSHOT_LV2_URI ">\n\ta lv2:Plugin , lv2:SpatialPlugin ;\n"
       "\tdoap:name \"Earshot binaural panner\" ;\n"
       "\tdoap:license <https://opensource.org/licenses/MIT> ;\n"
       "\tlv2:minorVersion 1 ;\n\tlv2:microVersion 0 ;\n"
       "\trdfs:comment \"A mono source placed around a head-tracked listener: HRTF from any SOFA set with "
       "fractional ITD, OpenAL's distance models, a room reverb; the head from a Wii Remote, opentrack, OSC or the "
       "simulator, shared by every instance in the process.\" ;\n"
       "\tlv2:optionalFeature lv2:hardRTCapable , urid:map , work:schedule , log:log ;\n"
       "\tlv2:extensionData work:interface , state:interface ;\n"
       "\tpatch:writable <" EARSHOT_LV2_SOFA "> , <" EARSHOT_LV2_TRACKER "> ;\n"
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

  std::string models;
  for (std::size_t i = 0; i < earshot::host::kDistanceModels.size(); ++i)
    models += std::string(i ? " , " : "\t\t\tlv2:scalePoint ") + "[ rdfs:label \"" +
              earshot::host::kDistanceModels[i].name + "\" ; rdf:value " + std::to_string(i) + " ]";
  models = "\t\t\tlv2:portProperty lv2:integer , lv2:enumeration ;\n" + models + " ;\n";
  std::string rooms = "\t\t\tlv2:portProperty lv2:integer , lv2:enumeration ;\n\t\t\tlv2:scalePoint [ rdfs:label "
                      "\"none\" ; rdf:value 0 ]";
  const auto presets = earshot::audio::room_presets();
  for (std::size_t i = 0; i < presets.size(); ++i)
    rooms += " , [ rdfs:label \"" + std::string(presets[i].name) + "\" ; rdf:value " + std::to_string(i + 1) + " ]";
  rooms += " ;\n";
  const std::string toggle = "\t\t\tlv2:portProperty lv2:toggled ;\n";
  const std::string sources =
      "\t\t\tlv2:portProperty lv2:integer , lv2:enumeration ;\n\t\t\tlv2:scalePoint [ rdfs:label \"wiimote\" ; "
      "rdf:value 0 ] , [ rdfs:label \"sim\" ; rdf:value 1 ] , [ rdfs:label \"opentrack\" ; rdf:value 2 ] , "
      "[ rdfs:label \"osc\" ; rdf:value 3 ] ;\n";
  const std::string trigger = "\t\t\tlv2:portProperty lv2:toggled , pprops:trigger ;\n";
  const std::string log_scale = "\t\t\tlv2:portProperty pprops:logarithmic ;\n";

  const Control inputs[] = {
      {"azimuth", "Azimuth (positive left)", 0, -180, 180, "degree", ""},
      {"elevation", "Elevation", 0, -90, 90, "degree", ""},
      {"distance", "Distance", 1, 0.1, 100, "m", log_scale.c_str()},
      {"gain", "Gain", 0, -60, 12, "db", ""},
      {"distance_model", "Distance model", 2, 0, 6, nullptr, models.c_str()},
      {"room", "Room", 0, 0, static_cast<double>(presets.size()), nullptr, rooms.c_str()},
      {"reverb_send", "Reverb send", -12, -60, 6, "db", ""},
      {"tracking", "Head tracking", 0, 0, 1, nullptr, toggle.c_str()},
      {"tracker_source", "Tracker", 0, 0, 3, nullptr, sources.c_str()},
      {"recenter", "Recenter", 0, 0, 1, nullptr, trigger.c_str()},
      {"yaw_offset", "Yaw offset (positive left)", 0, -180, 180, "degree", ""},
      {"pitch_offset", "Pitch offset (positive up)", 0, -90, 90, "degree", ""},
      {"roll_offset", "Roll offset (positive right)", 0, -180, 180, "degree", ""},
  };
  int index = 5;
  for (const auto& c : inputs) {
    control_port(o, index++, c);
    o << " ,\n";
  }
  const std::string latency = "\t\t\tlv2:designation lv2:latency ;\n\t\t\tlv2:portProperty lv2:reportsLatency , "
                              "lv2:integer ;\n";
  control_port(o, index++, {"latency", "Latency", 0, 0, 8192, "frame", latency.c_str()}, true);
  o << " ,\n";
  control_port(o, index++, {"head_yaw", "Head yaw", 0, -180, 180, "degree", ""}, true);
  o << " ,\n";
  control_port(o, index++, {"head_pitch", "Head pitch", 0, -90, 90, "degree", ""}, true);
  o << " ,\n";
  control_port(o, index++, {"head_roll", "Head roll", 0, -180, 180, "degree", ""}, true);
  o << " .\n";
  const bool ambi_ok = write_ambi_ttl(dir, library, manifest);
  if (!o || !manifest || !ambi_ok) {
    std::cerr << "earshot_lv2_ttl: cannot write the turtle into " << dir << "\n";
    return 1;
  }
  return 0;
}
