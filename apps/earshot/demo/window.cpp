#include "window.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <zlib.h>

#include "earshot/geometry.hpp"
#include "keys.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <vector>
#include <stdexcept>

namespace earshot::demo {
namespace {

using V3 = std::array<float, 3>;

/// The plugin hands the head's orientation as floats; the maths is common's.
earshot::Quat quat_of(const std::array<float, 4>& q) { return {q[0], q[1], q[2], q[3]}; }

/// v turned by orientation q, for drawing.
V3 rotate(const std::array<float, 4>& q, const V3& v) {
  const earshot::Vec3 r = earshot::rotate(quat_of(q), {v[0], v[1], v[2]});
  return {static_cast<float>(r[0]), static_cast<float>(r[1]), static_cast<float>(r[2])};
}

/// One 2D projection: screen x from axis `ax` (sign sx), screen y from axis `ay` (sign sy).
void view(const char* title, int ax, float sx, int ay, float sy, const char* axes, const WindowModel& m) {
  ImGui::BeginChild(title, ImVec2(0, 240), true);
  ImGui::TextUnformatted(title);
  ImGui::SameLine();
  ImGui::TextDisabled("%s", axes);
  ImDrawList* d = ImGui::GetWindowDrawList();
  const ImVec2 p0 = ImGui::GetCursorScreenPos(), size = ImGui::GetContentRegionAvail();
  const ImVec2 c(p0.x + size.x / 2, p0.y + size.y / 2);
  const float scale = std::min(size.x, size.y) / 12.0f;  // +-6 m
  auto at = [&](const V3& v) { return ImVec2(c.x + sx * v[ax] * scale, c.y - sy * v[ay] * scale); };
  for (float g = -6; g <= 6; g += 2) {
    d->AddLine(ImVec2(c.x + g * scale, p0.y), ImVec2(c.x + g * scale, p0.y + size.y), IM_COL32(60, 60, 70, 255));
    d->AddLine(ImVec2(p0.x, c.y + g * scale), ImVec2(p0.x + size.x, c.y + g * scale), IM_COL32(60, 60, 70, 255));
  }
  for (const auto& s : m.sources) {
    for (std::size_t i = 1; i < s.path.size(); ++i)
      d->AddLine(at(s.path[i - 1]), at(s.path[i]), IM_COL32(90, 140, 200, 160));
    d->AddCircleFilled(at(s.position), 6, IM_COL32(250, 190, 60, 255));
    const ImVec2 p = at(s.position);
    d->AddText(ImVec2(p.x + 8, p.y - 8), IM_COL32(255, 230, 180, 255), s.name.c_str());
  }
  const ImVec2 h = at(m.head_position);
  d->AddCircle(h, 10, IM_COL32(120, 240, 120, 255), 20, 2);
  const V3 f = rotate(m.head_orientation, {0, 0, -1}), up = rotate(m.head_orientation, {0, 1, 0});
  const V3 fh{m.head_position[0] + 0.8f * f[0], m.head_position[1] + 0.8f * f[1], m.head_position[2] + 0.8f * f[2]};
  const V3 uh{m.head_position[0] + 0.5f * up[0], m.head_position[1] + 0.5f * up[1], m.head_position[2] + 0.5f * up[2]};
  d->AddLine(h, at(fh), IM_COL32(120, 240, 120, 255), 3);  // nose: where the head looks
  d->AddLine(h, at(uh), IM_COL32(240, 120, 240, 200), 1.5f);  // up
  d->AddText(ImVec2(h.x + 12, h.y + 4), IM_COL32(160, 255, 160, 255), "head");
  ImGui::EndChild();
}

/// The tracker's camera image (its size: the Wii Remote's 1024 x 768, a
/// webcam's resolution; +x right, +y down), `width` wide with the camera's
/// aspect: the camera's picture when there is one (`picture`: its texture),
/// and over it the dots, each a circle as big as the camera says (when it
/// says), with the LED label.
void camera_view(const WindowModel& m, float width, ImTextureID picture) {
  const float cw = float(std::max(m.camera_width, 1)), ch = float(std::max(m.camera_height, 1));
  const float height = width * ch / cw;
  ImDrawList* d = ImGui::GetWindowDrawList();
  const ImVec2 p0 = ImGui::GetCursorScreenPos(), p1(p0.x + width, p0.y + height);
  d->AddRectFilled(p0, p1, IM_COL32(20, 20, 28, 255));
  const float k = width / cw;
  if (picture) {
    // A little dimmed, so the coloured dots and labels stand out on a bright frame.
    d->AddImage(picture, p0, p1, ImVec2(0, 0), ImVec2(1, 1), IM_COL32(190, 190, 190, 255));
  } else {
    for (float g = 1; g < 4; ++g) {  // quarter lines
      d->AddLine(ImVec2(p0.x + g * width / 4, p0.y), ImVec2(p0.x + g * width / 4, p1.y), IM_COL32(45, 45, 58, 255));
      d->AddLine(ImVec2(p0.x, p0.y + g * height / 4), ImVec2(p1.x, p0.y + g * height / 4), IM_COL32(45, 45, 58, 255));
    }
  }
  d->AddRect(p0, p1, IM_COL32(110, 110, 130, 255));
  static const ImU32 led_colour[4] = {IM_COL32(255, 90, 90, 255), IM_COL32(90, 220, 90, 255),
                                      IM_COL32(90, 160, 255, 255), IM_COL32(240, 220, 80, 255)};
  // Sizes are the Wii camera's 0..15 there; a webcam's are its own (a tag's
  // corners have none worth drawing): rings over its picture, the corner seen.
  const bool wii_sizes = !picture && m.camera_width == 1024 && m.camera_height == 768;
  // A printed tag's points are its corners (0 top-left, clockwise as printed), not LEDs.
  const char* point_name = m.tracker.find("beacon=apriltag") != std::string::npos ? "corner" : "LED";
  for (const auto& dot : m.dots) {
    const ImVec2 c(p0.x + dot.x * k, p0.y + dot.y * k);
    const float r = wii_sizes && dot.size >= 0 ? 3.0f + 0.8f * float(std::min(dot.size, 15)) : 5.0f;
    const ImU32 col = dot.label >= 0 && dot.label < 4 ? led_colour[dot.label] : IM_COL32(220, 220, 220, 255);
    if (picture) d->AddCircle(c, r, col, 16, 2.0f);
    else d->AddCircleFilled(c, r, col);
    char text[32];
    if (dot.label >= 0) std::snprintf(text, sizeof text, "%s %d", point_name, dot.label);
    else std::snprintf(text, sizeof text, "?");
    // Odd labels to the left, even to the right: the beacon's dots sit close together.
    const float left = dot.label % 2 != 0 ? ImGui::CalcTextSize(text).x + 2 * r + 6 : 0.0f;
    d->AddText(ImVec2(c.x + r + 3 - left, c.y - 7), col, text);
  }
  if (m.dots.empty())
    d->AddText(ImVec2(p0.x + 8, p0.y + height / 2 - 7), IM_COL32(150, 150, 160, 255), "no dots in view");
  char size_text[64];
  std::snprintf(size_text, sizeof size_text, "camera %d x %d, %zu dot%s", m.camera_width, m.camera_height,
                m.dots.size(), m.dots.size() == 1 ? "" : "s");
  d->AddText(ImVec2(p0.x + 4, p0.y + 2), IM_COL32(150, 150, 160, 255), size_text);
  ImGui::Dummy(ImVec2(width, height));
}

bool combo(const char* label, int* index, const std::vector<std::string>& items) {
  std::vector<const char*> names;
  names.reserve(items.size());
  for (const auto& r : items) names.push_back(r.c_str());
  return ImGui::Combo(label, index, names.data(), int(names.size()), 12);
}

ImVec4 state_colour(const std::string& state) {
  if (state == "tracking") return ImVec4(0.45f, 0.95f, 0.45f, 1);
  if (state == "connected" || state == "searching") return ImVec4(1.0f, 0.85f, 0.35f, 1);
  if (state == "none") return ImVec4(0.7f, 0.7f, 0.7f, 1);
  return ImVec4(1.0f, 0.45f, 0.35f, 1);  // lost, disconnected, failed
}

}  // namespace

struct DemoWindow::Impl {
  GLFWwindow* window = nullptr;
  int width = 1280, height = 900;
  std::array<char, 512> file{};
  // The camera's picture as a texture, uploaded when its frame changes.
  GLuint picture = 0;
  std::uint32_t picture_frame = 0;
  int picture_width = 0, picture_height = 0;
  std::vector<unsigned char> rgba;
  long uploads = 0;

  ImTextureID upload_picture(const WindowModel& m);
};

long DemoWindow::pictures() const { return impl_->uploads; }

/// The model's picture as a texture (null: none); grey spread to RGBA, as
/// every OpenGL 3 context takes it.
ImTextureID DemoWindow::Impl::upload_picture(const WindowModel& m) {
  const int w = m.picture_width, h = m.picture_height;
  if (m.picture.empty() || w <= 0 || h <= 0 || m.picture.size() < std::size_t(w) * std::size_t(h)) return nullptr;
  const bool fresh = !picture || w != picture_width || h != picture_height;
  if (fresh || m.picture_frame != picture_frame) {
    rgba.resize(std::size_t(w) * std::size_t(h) * 4);
    for (std::size_t i = 0; i < std::size_t(w) * std::size_t(h); ++i) {
      const unsigned char g = m.picture[i];
      rgba[4 * i] = rgba[4 * i + 1] = rgba[4 * i + 2] = g;
      rgba[4 * i + 3] = 255;
    }
    if (!picture) glGenTextures(1, &picture);
    glBindTexture(GL_TEXTURE_2D, picture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (fresh) {
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
      glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    } else {
      glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
    }
    picture_width = w, picture_height = h, picture_frame = m.picture_frame;
    ++uploads;
  }
  return reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(picture));
}

bool window_available() { return true; }

DemoWindow::DemoWindow(const std::string& title) : impl_(std::make_unique<Impl>()) {
  if (!glfwInit()) throw std::runtime_error("no display (GLFW could not start)");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 0);
  impl_->window = glfwCreateWindow(impl_->width, impl_->height, title.c_str(), nullptr, nullptr);
  if (!impl_->window) {
    glfwTerminate();
    throw std::runtime_error("no display (no OpenGL 3 window)");
  }
  glfwMakeContextCurrent(impl_->window);
  glfwSwapInterval(1);  // vsync where there is one (not under Xvfb: the control loop paces frames)
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsDark();
  // Rendered in software (Mesa's llvmpipe under Xvfb), anti-aliased lines and
  // fills are many more triangles to rasterise on the CPU the audio needs.
  const auto* r = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
  renderer_ = r ? r : "";
  software_ = renderer_.find("llvmpipe") != std::string::npos || renderer_.find("softpipe") != std::string::npos ||
              renderer_.find("swrast") != std::string::npos;
  if (software_) ImGui::GetStyle().AntiAliasedLines = ImGui::GetStyle().AntiAliasedFill = false;
  ImGui_ImplGlfw_InitForOpenGL(impl_->window, true);
  ImGui_ImplOpenGL3_Init("#version 130");
}

DemoWindow::~DemoWindow() {
  if (impl_->picture) glDeleteTextures(1, &impl_->picture);
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(impl_->window);
  glfwTerminate();
}

namespace {

/// No remote, disconnected: said in a banner so nobody misses it.
void tracker_banner(const WindowModel& m) {
  ImGui::PushStyleColor(ImGuiCol_ChildBg, ImVec4(0.45f, 0.12f, 0.08f, 1));
  ImGui::BeginChild("banner", ImVec2(0, 58), true);
  ImGui::SetWindowFontScale(1.4f);
  ImGui::TextColored(ImVec4(1, 0.85f, 0.6f, 1), "Tracker %s: %s", m.tracker.c_str(), m.tracker_state.c_str());
  ImGui::SetWindowFontScale(1.0f);
  ImGui::TextWrapped("%s", m.tracker_message.c_str());
  ImGui::EndChild();
  ImGui::PopStyleColor();
}

/// The window's keys (keys.hpp); not while a file name is typed.
void read_keys(WindowActions& a) {
  if (ImGui::GetIO().WantTextInput) return;
  if (ImGui::IsKeyPressed(GLFW_KEY_R, false)) a.recenter = true;
  if (ImGui::IsKeyPressed(GLFW_KEY_N, false)) a.next_scene = true;
  if (ImGui::IsKeyPressed(GLFW_KEY_M, false)) a.next_room = true;
  if (ImGui::IsKeyPressed(GLFW_KEY_H, false)) a.next_hrtf = true;
  if (ImGui::IsKeyPressed(GLFW_KEY_Q, false) || ImGui::IsKeyPressed(GLFW_KEY_ESCAPE, false)) a.quit = true;
}

void tracker_column(const WindowModel& m, ImTextureID picture) {
  ImGui::TextUnformatted("Tracker");
  ImGui::SameLine();
  ImGui::TextColored(state_colour(m.tracker_state), "%s", m.tracker_state.c_str());
  ImGui::SameLine();
  ImGui::TextDisabled("(%s)", m.tracker.c_str());
  ImGui::Text("%.0f frames/s   %llu frames   yaw %+.1f deg", double(m.tracker_rate), m.tracker_frames,
              earshot::ypr_from_quat(quat_of(m.head_orientation)).yaw * 180.0 / 3.14159265358979);
  camera_view(m, 288, picture);
  if (!m.tracker_message.empty() && !m.tracker_alarm) ImGui::TextWrapped("%s", m.tracker_message.c_str());
}

/// Audio load and xruns, the buttons, the keys, the last message.
void audio_column(const WindowModel& m, WindowActions& a) {
  ImGui::TextUnformatted("Audio");
  ImGui::Text("load %.1f%% (max %.1f%%) of one core", 100 * m.load, 100 * m.load_max);
  if (m.xruns > 0) ImGui::TextColored(ImVec4(1, 0.45f, 0.35f, 1), "xruns %llu", m.xruns);
  else ImGui::Text("xruns 0");
  ImGui::SameLine();
  ImGui::Text("  blocks %llu", m.blocks);
  ImGui::Text("HRTF %s", m.hrtf.c_str());
  ImGui::SameLine();
  if (ImGui::Button("Next (H)")) a.next_hrtf = true;
  if (ImGui::Button("Recenter (R)")) a.recenter = true;
  ImGui::SameLine();
  if (ImGui::Button("Quit (Q / Esc)")) a.quit = true;
  ImGui::Separator();
  ImGui::TextUnformatted("Keys");
  for (const auto& k : kKeys) ImGui::Text("  %-9s %s", k.keys, k.does);
  if (!m.message.empty()) {
    ImGui::Separator();
    ImGui::PushStyleColor(ImGuiCol_Text, ImVec4(1, 0.55f, 0.45f, 1));
    ImGui::TextWrapped("%s", m.message.c_str());
    ImGui::PopStyleColor();
  }
}

/// Source `i`'s controls: sound, path or position, gain and distance.
void source_controls(WindowModel& m, std::size_t i, WindowActions& a) {
  auto& s = m.sources[i];
  const int id = int(i);
  ImGui::PushID(id);
  char header[160];
  std::snprintf(header, sizeof header, "%s   (%.1f, %.1f, %.1f) m%s###src", s.name.c_str(), s.position[0],
                s.position[1], s.position[2], s.path.empty() ? "" : ", moving");
  if (ImGui::CollapsingHeader(header, i < 2 ? ImGuiTreeNodeFlags_DefaultOpen : 0)) {
    ImGui::PushItemWidth(170);
    if (combo("sound", &s.sound, m.sounds)) a.changed_sounds.push_back(id);
    ImGui::SameLine();
    if (combo("path", &s.path_choice, m.paths)) a.changed_paths.push_back(id);
    if (s.path.empty() && ImGui::DragFloat3("position m", s.position.data(), 0.05f, -50, 50, "%.2f"))
      a.changed_positions.push_back(id);
    bool ch = ImGui::SliderFloat("gain dB", &s.gain_db, -40, 12, "%.1f");
    ImGui::SameLine();
    ch |= combo("distance", &s.distance_model, m.distance_models);
    ch |= ImGui::SliderFloat("rolloff", &s.rolloff, 0, 4, "%.2f");
    ImGui::SameLine();
    ch |= ImGui::SliderFloat("ref. m", &s.reference_distance, 0.1f, 10, "%.2f");
    if (ch) a.changed_sources.push_back(id);
    ImGui::PopItemWidth();
  }
  ImGui::PopID();
}

/// The scene, room and file pickers, then every source's controls.
void controls_column(WindowModel& m, std::array<char, 512>& file, WindowActions& a) {
  ImGui::PushItemWidth(200);
  if (combo("Scene", &m.scene_index, m.scenes)) a.scene_changed = true;
  ImGui::SameLine();
  if (combo("Room", &m.room_index, m.rooms)) a.room_changed = true;
  ImGui::InputTextWithHint("##file", "scene file (.json)", file.data(), file.size());
  ImGui::SameLine();
  if (ImGui::Button("Load file") && file[0]) {
    a.load_file = true;
    m.scene_file_input = file.data();
  }
  ImGui::PopItemWidth();
  ImGui::BeginChild("sources", ImVec2(0, 0), false);
  for (std::size_t i = 0; i < m.sources.size(); ++i) source_controls(m, i, a);
  ImGui::EndChild();
}

}  // namespace

WindowActions DemoWindow::frame(WindowModel& m) {
  WindowActions a;
  if (frames_ > 0) glfwSwapBuffers(impl_->window);
  glfwPollEvents();
  if (glfwWindowShouldClose(impl_->window)) a.quit = true;
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  read_keys(a);

  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImGui::GetIO().DisplaySize);
  ImGui::Begin("earshot demo", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove);
  ImGui::Text("Scene %s   room %s   device %s (output latency %.1f ms)   t %.1f s", m.scene.c_str(),
              m.room.c_str(), m.device.c_str(), m.latency_ms, m.time_s);
  if (m.tracker_alarm) tracker_banner(m);
  if (ImGui::BeginTable("views", 3)) {
    ImGui::TableNextColumn();
    view("Top", 0, 1, 2, -1, "(x right, -z up = ahead)", m);
    ImGui::TableNextColumn();
    view("Front", 0, 1, 1, 1, "(x right, y up)", m);
    ImGui::TableNextColumn();
    view("Side", 2, -1, 1, 1, "(-z right = ahead, y up)", m);
    ImGui::EndTable();
  }
  if (ImGui::BeginTable("lower", 3, ImGuiTableFlags_BordersInnerV)) {
    ImGui::TableSetupColumn("tracker", ImGuiTableColumnFlags_WidthFixed, 300);
    ImGui::TableSetupColumn("audio", ImGuiTableColumnFlags_WidthFixed, 330);
    ImGui::TableSetupColumn("controls", ImGuiTableColumnFlags_WidthStretch);
    ImGui::TableNextColumn();
    tracker_column(m, impl_->upload_picture(m));
    ImGui::TableNextColumn();
    audio_column(m, a);
    ImGui::TableNextColumn();
    controls_column(m, impl_->file, a);
    ImGui::EndTable();
  }
  ImGui::End();
  ImGui::Render();
  glfwGetFramebufferSize(impl_->window, &impl_->width, &impl_->height);
  glViewport(0, 0, impl_->width, impl_->height);
  glClearColor(0.08f, 0.08f, 0.1f, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  ++frames_;
  return a;
}

void DemoWindow::screenshot(const std::filesystem::path& png) const {
  const int w = impl_->width, h = impl_->height;
  std::vector<unsigned char> rgb(std::size_t(w) * h * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
  // PNG rows are top first, with a filter byte (0) each.
  std::vector<unsigned char> raw;
  raw.reserve(std::size_t(h) * (1 + 3 * std::size_t(w)));
  for (int y = h - 1; y >= 0; --y) {
    raw.push_back(0);
    raw.insert(raw.end(), rgb.begin() + std::ptrdiff_t(y) * w * 3, rgb.begin() + std::ptrdiff_t(y + 1) * w * 3);
  }
  uLongf zn = compressBound(uLong(raw.size()));
  std::vector<unsigned char> z(zn);
  compress2(z.data(), &zn, raw.data(), uLong(raw.size()), 6);
  z.resize(zn);
  std::ofstream f(png, std::ios::binary);
  if (!f) throw std::runtime_error("cannot write " + png.string());
  auto be32 = [](std::vector<unsigned char>& v, std::uint32_t x) {
    for (int s = 24; s >= 0; s -= 8) v.push_back(static_cast<unsigned char>(x >> s));
  };
  auto chunk = [&](const char* type, const std::vector<unsigned char>& data) {
    std::vector<unsigned char> c;
    be32(c, std::uint32_t(data.size()));
    c.insert(c.end(), type, type + 4);
    c.insert(c.end(), data.begin(), data.end());
    std::vector<unsigned char> crc;
    be32(crc, std::uint32_t(crc32(0, c.data() + 4, uInt(c.size() - 4))));
    c.insert(c.end(), crc.begin(), crc.end());
    f.write(reinterpret_cast<const char*>(c.data()), std::streamsize(c.size()));
  };
  f.write("\x89PNG\r\n\x1a\n", 8);
  std::vector<unsigned char> ihdr;
  be32(ihdr, std::uint32_t(w)), be32(ihdr, std::uint32_t(h));
  ihdr.insert(ihdr.end(), {8, 2, 0, 0, 0});
  chunk("IHDR", ihdr);
  chunk("IDAT", z);
  chunk("IEND", {});
}

}  // namespace earshot::demo
