#include "window.hpp"

#include <GLFW/glfw3.h>
#include <imgui.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <zlib.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

namespace earshot::demo {
namespace {

using V3 = std::array<float, 3>;

V3 rotate(const std::array<float, 4>& q, const V3& v) {
  const V3 u{q[1], q[2], q[3]};
  auto cross = [](const V3& a, const V3& b) {
    return V3{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  };
  const V3 c1 = cross(u, v), c2 = cross(u, c1);
  return {v[0] + 2 * (q[0] * c1[0] + c2[0]), v[1] + 2 * (q[0] * c1[1] + c2[1]), v[2] + 2 * (q[0] * c1[2] + c2[2])};
}

/// One 2D projection: screen x from axis `ax` (sign sx), screen y from axis `ay` (sign sy).
void view(const char* title, int ax, float sx, int ay, float sy, const char* axes, const WindowModel& m) {
  ImGui::BeginChild(title, ImVec2(0, 250), true);
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

}  // namespace

struct DemoWindow::Impl {
  GLFWwindow* window = nullptr;
  int width = 1280, height = 860;
};

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
  glfwSwapInterval(1);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(impl_->window, true);
  ImGui_ImplOpenGL3_Init("#version 130");
}

DemoWindow::~DemoWindow() {
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(impl_->window);
  glfwTerminate();
}

WindowActions DemoWindow::frame(WindowModel& m) {
  WindowActions a;
  if (frames_ > 0) glfwSwapBuffers(impl_->window);
  glfwPollEvents();
  if (glfwWindowShouldClose(impl_->window)) a.quit = true;
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  if (ImGui::IsKeyPressed(GLFW_KEY_R)) a.recenter = true;
  if (ImGui::IsKeyPressed(GLFW_KEY_Q) || ImGui::IsKeyPressed(GLFW_KEY_ESCAPE)) a.quit = true;

  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImGui::GetIO().DisplaySize);
  ImGui::Begin("earshot demo", nullptr, ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove);
  ImGui::Text("Scene %s   device %s (%.1f ms)   t %.1f s", m.scene.c_str(), m.device.c_str(), m.latency_ms,
              m.time_s);
  if (ImGui::BeginTable("views", 3)) {
    ImGui::TableNextColumn();
    view("Top", 0, 1, 2, -1, "(x right, -z up = ahead)", m);
    ImGui::TableNextColumn();
    view("Front", 0, 1, 1, 1, "(x right, y up)", m);
    ImGui::TableNextColumn();
    view("Side", 2, -1, 1, 1, "(-z right = ahead, y up)", m);
    ImGui::EndTable();
  }
  if (ImGui::BeginTable("lower", 2)) {
    ImGui::TableNextColumn();
    ImGui::Separator();
    ImGui::TextUnformatted("Tracker and audio");
    const V3 f = rotate(m.head_orientation, {0, 0, -1});
    ImGui::Text("Tracker %s   head yaw %+.1f deg", m.tracker.c_str(),
                std::atan2(-f[0], -f[2]) * 180.0 / 3.14159265358979);
    ImGui::Text("Audio load %.1f%% (max %.1f%%) of one core   xruns %llu   blocks %llu", 100 * m.load,
                100 * m.load_max, m.xruns, m.blocks);
    if (!m.message.empty()) ImGui::TextColored(ImVec4(1, 0.5f, 0.4f, 1), "%s", m.message.c_str());
    if (ImGui::Button("Recenter (R)")) a.recenter = true;
    ImGui::SameLine();
    if (ImGui::Button("Quit (Q / Esc)")) a.quit = true;
    ImGui::TextDisabled("Keys: R recenter the head, Q or Esc quit");
    ImGui::TextDisabled("Camera dots: not published by the plugin's C API yet");
    ImGui::TableNextColumn();
    ImGui::Separator();
    ImGui::TextUnformatted("Controls");
    if (!m.rooms.empty()) {
      std::vector<const char*> names;
      for (const auto& r : m.rooms) names.push_back(r.c_str());
      if (ImGui::Combo("Room", &m.room_index, names.data(), int(names.size()))) a.room_changed = true;
    }
    for (std::size_t i = 0; i < m.sources.size(); ++i) {
      auto& s = m.sources[i];
      ImGui::PushID(int(i));
      ImGui::Text("%s  (%.1f, %.1f, %.1f) m%s", s.name.c_str(), s.position[0], s.position[1], s.position[2],
                  s.path.empty() ? "" : ", on a path");
      bool ch = ImGui::SliderFloat("gain dB", &s.gain_db, -40, 12);
      ch |= ImGui::SliderFloat("rolloff", &s.rolloff, 0, 4);
      if (ch) a.changed_sources.push_back(int(i));
      ImGui::PopID();
    }
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
