// click_test: how clean a turning head sounds. A 500 Hz sine 1 m straight
// ahead while the listener yaws at 360 deg/s, the pose updated every
// 128-frame block at 48 kHz, rendered by Earshot's Renderer (MIT KEMAR) and
// by OpenAL Soft (HRTF, loopback). A time-invariant filter cannot move a sine
// off 500 Hz, so everything above 2 kHz is an artefact of the head turning
// (filter switching, block steps, delay jumps): we report that energy
// relative to the total, per ear (Welch, Hann window), beside a static head.
// Prints markdown for docs/BENCHMARKS.md.
//
//   click_test [--seconds 5] [--skip 0.5] [--wav-dir DIR] [--require-db -60]
//              [--blend floored|plain|nearest] [--bed-orders 1,3,5]
//              [--tier-orders 3] [--require-bed-db -80]
//
// --blend: Earshot's filter blend (HrtfSet::FilterBlend; floored is the
// default).
// --require-db: exit 1 when Earshot's turning-head ratio on either ear is
// above that level (a quality check, not a timing one).
// --bed-orders: also the same tone as an Ambisonic bed (a plane wave from
// ahead, ambiX, that order) through a whole world of the C API
// (libearshot: esCreateAmbisonicBuffer, the head by esSetHeadPose every
// block), and --tier-orders: the point source through a world with the
// Ambisonic tier (ES_QUALITY_AMBISONIC(N)). --require-bed-db: exit 1 when a
// bed's or a tier's turning ratio is above that level.
#include <kiss_fftr.h>
#include <sndfile.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include "earshot/audio/ambisonics/spherical_harmonics.hpp"
#include "earshot/audio/renderer.hpp"
#include "earshot/earshot.h"
#include "openal_reference.hpp"

namespace {

constexpr int kRate = 48000;
constexpr std::size_t kBlock = 128;
constexpr double kToneHz = 500.0;
constexpr double kAmplitude = 0.25;  // far below the limiter's threshold
constexpr double kYawRate = 2 * std::numbers::pi;  // rad/s
constexpr double kSplitHz = 2000.0;

struct Stereo {
  std::vector<float> left, right;
};

/// One second of the tone: exactly 500 periods, so it loops without a seam.
std::vector<float> tone_second() {
  std::vector<float> x(kRate);
  for (std::size_t n = 0; n < x.size(); ++n)
    x[n] = float(kAmplitude * std::sin(2 * std::numbers::pi * kToneHz * double(n) / kRate));
  return x;
}

double yaw_at_block(std::size_t b, bool turning) {
  return turning ? kYawRate * double(b * kBlock) / kRate : 0.0;
}

Stereo render_earshot(std::size_t blocks, bool turning, const std::shared_ptr<const earshot::hrtf::HrtfSet>& hrtf) {
  earshot::audio::RendererConfig cfg;
  cfg.sample_rate = kRate;
  cfg.block = kBlock;
  earshot::audio::Renderer r(hrtf, cfg);
  earshot::audio::SourceState src;
  src.position = {0, 0, -1};
  const int id = r.add_source(src);
  const std::vector<float> tone = tone_second();
  Stereo out{std::vector<float>(blocks * kBlock), std::vector<float>(blocks * kBlock)};
  for (std::size_t b = 0; b < blocks; ++b) {
    earshot::HeadPose l;
    l.orientation = earshot::quat_from_ypr(yaw_at_block(b, turning), 0, 0);
    r.set_listener(l);
    std::span<float> in = r.source_input(id);
    for (std::size_t n = 0; n < kBlock; ++n) in[n] = tone[(b * kBlock + n) % tone.size()];
    r.render(std::span(out.left).subspan(b * kBlock, kBlock), std::span(out.right).subspan(b * kBlock, kBlock));
  }
  return out;
}

Stereo render_openal(std::size_t blocks, bool turning, std::string& hrtf_name) {
  earshot::bench::OpenAlReference al({.sample_rate = kRate, .sources = 1});
  hrtf_name = "\"" + al.hrtf_name() + "\" (available:";
  for (const std::string& h : al.available_hrtfs()) hrtf_name += " \"" + h + "\"";
  hrtf_name += ")";
  const std::vector<float> tone = tone_second();
  al.set_source_position(0, {0, 0, -1});
  al.play_loop(0, al.add_buffer(tone));
  Stereo out{std::vector<float>(blocks * kBlock), std::vector<float>(blocks * kBlock)};
  for (std::size_t b = 0; b < blocks; ++b) {
    al.set_listener_orientation(earshot::quat_from_ypr(yaw_at_block(b, turning), 0, 0));
    al.render(std::span(out.left).subspan(b * kBlock, kBlock), std::span(out.right).subspan(b * kBlock, kBlock));
  }
  return out;
}

/// The tone through a world of the C API, the head turned by esSetHeadPose
/// each block: as an order-`bed` Ambisonic bed (a plane wave from ahead),
/// or (bed 0) as a point source 1 m ahead in a world of the tier `tier`.
Stereo render_world(std::size_t blocks, bool turning, int bed, int tier) {
  ESworldparams p;
  esWorldParamsDefault(&p);
  p.sample_rate = kRate;
  p.block_size = kBlock;
  p.max_sources = 1;
  ESworld w = 0;
  if (esCreateWorld(&p, &w) != ES_OK) throw std::runtime_error(std::string("esCreateWorld: ") + esGetErrorMessage(0));
  struct Destroy {
    ESworld w;
    ~Destroy() { esDestroyWorld(w); }
  } destroy{w};
  const auto check = [&](ESenum e, const char* what) {
    if (e != ES_OK) throw std::runtime_error(std::string(what) + ": " + esGetErrorMessage(w));
  };
  if (tier > 0) check(esWorldi(w, ES_QUALITY, ES_QUALITY_AMBISONIC(tier)), "ES_QUALITY");
  const std::vector<float> tone = tone_second();
  ESbuffer b = 0;
  if (bed > 0) {
    const std::size_t C = earshot::ambisonics::channel_count(bed);
    std::vector<double> sh(C);
    earshot::ambisonics::real_sh(bed, earshot::Vec3{1, 0, 0}, sh);  // ahead
    std::vector<float> field(tone.size() * C);
    for (std::size_t n = 0; n < tone.size(); ++n)
      for (std::size_t c = 0; c < C; ++c) field[n * C + c] = static_cast<float>(sh[c]) * tone[n];
    check(esCreateAmbisonicBuffer(w, field.data(), static_cast<ESuint>(tone.size()), kRate, static_cast<ESuint>(bed),
                                  ES_AMBISONIC_LAYOUT_ACN, ES_AMBISONIC_SCALING_SN3D, &b),
          "esCreateAmbisonicBuffer");
  } else {
    check(esCreateBuffer(w, tone.data(), static_cast<ESuint>(tone.size()), kRate, &b), "esCreateBuffer");
  }
  ESsource s = 0;
  check(esCreateSource(w, &s), "esCreateSource");
  check(esSourcei(w, s, ES_BUFFER, static_cast<ESint>(b)), "ES_BUFFER");
  check(esSourcei(w, s, ES_LOOPING, ES_TRUE), "ES_LOOPING");
  if (bed == 0) check(esSource3f(w, s, ES_POSITION, 0, 0, -1), "ES_POSITION");
  check(esSourcePlay(w, s), "esSourcePlay");
  Stereo out{std::vector<float>(blocks * kBlock), std::vector<float>(blocks * kBlock)};
  for (std::size_t k = 0; k < blocks; ++k) {
    const earshot::Quat q = earshot::quat_from_ypr(yaw_at_block(k, turning), 0, 0);
    const ESfloat pos[3] = {0, 0, 0};
    const ESfloat o[4] = {static_cast<ESfloat>(q[0]), static_cast<ESfloat>(q[1]), static_cast<ESfloat>(q[2]),
                          static_cast<ESfloat>(q[3])};
    check(esSetHeadPose(w, pos, o), "esSetHeadPose");
    if (esRender(w, out.left.data() + k * kBlock, out.right.data() + k * kBlock, kBlock) != ES_OK)
      throw std::runtime_error("esRender failed");
  }
  return out;
}

/// Welch power spectrum: Hann-windowed segments, half overlapping, averaged.
class Welch {
 public:
  explicit Welch(std::size_t nfft)
      : nfft_(nfft), cfg_(kiss_fftr_alloc(int(nfft), 0, nullptr, nullptr)), window_(nfft), frame_(nfft),
        bins_(nfft / 2 + 1) {
    if (!cfg_) throw std::runtime_error("kiss_fftr_alloc failed");
    for (std::size_t n = 0; n < nfft; ++n)
      window_[n] = float(0.5 - 0.5 * std::cos(2 * std::numbers::pi * double(n) / double(nfft)));
  }

  [[nodiscard]] std::vector<double> psd(std::span<const float> x) {
    std::vector<double> p(nfft_ / 2 + 1, 0.0);
    const std::size_t hop = nfft_ / 2;
    if (x.size() < nfft_) throw std::runtime_error("signal shorter than one analysis segment");
    for (std::size_t start = 0; start + nfft_ <= x.size(); start += hop) {
      for (std::size_t n = 0; n < nfft_; ++n) frame_[n] = x[start + n] * window_[n];
      kiss_fftr(cfg_.get(), frame_.data(), bins_.data());
      for (std::size_t k = 0; k < p.size(); ++k)
        p[k] += double(bins_[k].r) * bins_[k].r + double(bins_[k].i) * bins_[k].i;
    }
    return p;  // unnormalised: only ratios are used
  }
  [[nodiscard]] double bin_hz(std::size_t k) const { return double(k) * kRate / double(nfft_); }

 private:
  struct FftrFree {
    void operator()(kiss_fftr_cfg c) const { kiss_fftr_free(c); }
  };
  std::size_t nfft_;
  std::unique_ptr<std::remove_pointer_t<kiss_fftr_cfg>, FftrFree> cfg_;
  std::vector<float> window_, frame_;
  std::vector<kiss_fft_cpx> bins_;
};

double db(double ratio) { return 10 * std::log10(std::max(ratio, 1e-30)); }

struct EarAnalysis {
  double high_db = 0;                 // energy above 2 kHz / total
  std::array<double, 4> bands_db{};   // 2-4, 4-8, 8-16, 16-24 kHz / total
  std::vector<std::pair<double, double>> peaks;  // (Hz, dB re total), loudest first
};

EarAnalysis analyse(Welch& w, std::span<const float> x) {
  const std::vector<double> p = w.psd(x);
  double total = 0, high = 0;
  std::array<double, 4> bands{};
  constexpr std::array<double, 5> edges{2000, 4000, 8000, 16000, 24001};
  for (std::size_t k = 0; k < p.size(); ++k) {
    total += p[k];
    const double f = w.bin_hz(k);
    if (f < kSplitHz) continue;
    high += p[k];
    for (std::size_t e = 0; e < 4; ++e)
      if (f >= edges[e] && f < edges[e + 1]) bands[e] += p[k];
  }
  EarAnalysis a;
  a.high_db = db(high / total);
  for (std::size_t e = 0; e < 4; ++e) a.bands_db[e] = db(bands[e] / total);
  for (std::size_t k = 1; k + 1 < p.size(); ++k)
    if (w.bin_hz(k) >= kSplitHz && p[k] > p[k - 1] && p[k] >= p[k + 1])
      a.peaks.emplace_back(w.bin_hz(k), db((p[k - 1] + p[k] + p[k + 1]) / total));
  std::sort(a.peaks.begin(), a.peaks.end(), [](const auto& u, const auto& v) { return u.second > v.second; });
  if (a.peaks.size() > 6) a.peaks.resize(6);
  return a;
}

void write_wav(const std::filesystem::path& path, const Stereo& s) {
  SF_INFO info{};
  info.samplerate = kRate;
  info.channels = 2;
  info.format = SF_FORMAT_WAV | SF_FORMAT_FLOAT;
  struct Closer {
    void operator()(SNDFILE* f) const { sf_close(f); }
  };
  std::unique_ptr<SNDFILE, Closer> f(sf_open(path.c_str(), SFM_WRITE, &info));
  if (!f) throw std::runtime_error("cannot write " + path.string() + ": " + sf_strerror(nullptr));
  std::vector<float> inter(2 * s.left.size());
  for (std::size_t n = 0; n < s.left.size(); ++n) {
    inter[2 * n] = s.left[n];
    inter[2 * n + 1] = s.right[n];
  }
  sf_writef_float(f.get(), inter.data(), sf_count_t(s.left.size()));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("Energy above 2 kHz of a 500 Hz tone ahead while the head yaws at 360 deg/s");
  double seconds = 5.0, skip = 0.5;
  std::string wav_dir;
  std::optional<double> require_db;
  app.add_option("--seconds", seconds, "length of each render")->check(CLI::Range(0.1, 600.0));
  app.add_option("--skip", skip, "seconds left out of the analysis at the start (the tone's onset)")
      ->check(CLI::Range(0.0, 60.0));
  app.add_option("--wav-dir", wav_dir, "write each render there as a float WAV");
  app.add_option("--require-db", require_db, "fail when Earshot's turning ratio exceeds this (dB)");
  std::vector<int> bed_orders, tier_orders;
  std::optional<double> require_bed_db;
  app.add_option("--bed-orders", bed_orders, "also the tone as an Ambisonic bed of these orders, through a world")
      ->delimiter(',')
      ->check(CLI::Range(1, 7));
  app.add_option("--tier-orders", tier_orders, "also the point source through a world of the ambisonic:N tier")
      ->delimiter(',')
      ->check(CLI::Range(1, 7));
  app.add_option("--require-bed-db", require_bed_db, "fail when a bed's or tier's turning ratio exceeds this (dB)");
  using Blend = earshot::hrtf::HrtfSet::FilterBlend;
  Blend blend = Blend::floored;
  app.add_option("--blend", blend, "Earshot's filter blend: floored (the default), plain or nearest")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, Blend>{{"floored", Blend::floored}, {"plain", Blend::plain}, {"nearest", Blend::nearest}}));
  CLI11_PARSE(app, argc, argv);

  try {
    const auto blocks = std::size_t(std::ceil(seconds * kRate / double(kBlock)));
    constexpr std::size_t kNfft = 4096;
    const std::size_t from = std::min(std::size_t(skip * kRate), blocks * kBlock - std::min(blocks * kBlock, kNfft));
    auto set = std::make_shared<earshot::hrtf::HrtfSet>(earshot::hrtf::HrtfSet::load_default(kRate));
    set->set_filter_blend(blend);
    const std::shared_ptr<const earshot::hrtf::HrtfSet> hrtf = std::move(set);
    Welch welch(kNfft);

    struct Run {
      std::string renderer;
      bool turning;
      Stereo out;
      EarAnalysis l, r;
    };
    std::vector<Run> runs;
    std::string al_hrtf;
    for (bool turning : {true, false}) {
      runs.push_back({"Earshot", turning, render_earshot(blocks, turning, hrtf), {}, {}});
      runs.push_back({"OpenAL Soft 1.19", turning, render_openal(blocks, turning, al_hrtf), {}, {}});
    }
    for (int order : bed_orders)
      for (bool turning : {true, false})
        runs.push_back({"Earshot world, bed order " + std::to_string(order), turning,
                        render_world(blocks, turning, order, 0), {}, {}});
    for (int order : tier_orders)
      for (bool turning : {true, false})
        runs.push_back({"Earshot world, ambisonic:" + std::to_string(order) + " tier", turning,
                        render_world(blocks, turning, 0, order), {}, {}});
    for (Run& run : runs) {
      run.l = analyse(welch, std::span<const float>(run.out.left).subspan(from));
      run.r = analyse(welch, std::span<const float>(run.out.right).subspan(from));
      if (!wav_dir.empty()) {
        std::filesystem::create_directories(wav_dir);
        std::string stem = run.renderer == "Earshot" ? "earshot" : run.renderer.starts_with("OpenAL") ? "openal" : run.renderer;
        for (char& ch : stem)
          if (ch == ' ' || ch == ',' || ch == ':') ch = '_';
        const std::string name = stem + (run.turning ? "_turning" : "_static") + ".wav";
        write_wav(std::filesystem::path(wav_dir) / name, run.out);
      }
    }

    std::printf("### 500 Hz tone 1 m ahead, head yawing at 360 deg/s (pose every %zu frames, %d Hz)\n\n", kBlock,
                kRate);
    std::printf("%.2f s rendered, the first %.2f s left out; Welch, Hann window, %zu-point segments, 50%% overlap.\n",
                double(blocks * kBlock) / kRate, double(from) / kRate, kNfft);
    std::printf("Earshot: MIT KEMAR (%s), %zu-tap filters at %d Hz. OpenAL Soft HRTF data set: %s.\n\n",
                earshot::hrtf::HrtfSet::kDefaultPath, hrtf->filter_length(), kRate, al_hrtf.c_str());
    std::printf("| renderer | head | left ear, energy > 2 kHz (dB re total) | right ear (dB re total) |\n");
    std::printf("|---|---|---|---|\n");
    for (const Run& run : runs)
      std::printf("| %s | %s | %.1f | %.1f |\n", run.renderer.c_str(), run.turning ? "yawing 360 deg/s" : "static",
                  run.l.high_db, run.r.high_db);

    std::printf("\nWhere the high-band energy sits (turning head; dB re the ear's total):\n\n");
    std::printf("| renderer | ear | 2-4 kHz | 4-8 kHz | 8-16 kHz | 16-24 kHz | loudest peaks above 2 kHz (Hz: dB) |\n");
    std::printf("|---|---|---|---|---|---|---|\n");
    for (const Run& run : runs) {
      if (!run.turning) continue;
      for (int ear = 0; ear < 2; ++ear) {
        const EarAnalysis& a = ear == 0 ? run.l : run.r;
        std::string peaks;
        for (const auto& [hz, d] : a.peaks) {
          char buf[48];
          std::snprintf(buf, sizeof buf, "%s%.0f: %.1f", peaks.empty() ? "" : ", ", hz, d);
          peaks += buf;
        }
        std::printf("| %s | %s | %.1f | %.1f | %.1f | %.1f | %s |\n", run.renderer.c_str(), ear == 0 ? "left" : "right",
                    a.bands_db[0], a.bands_db[1], a.bands_db[2], a.bands_db[3], peaks.c_str());
      }
    }

    if (require_bed_db) {
      double worst = -1e9;
      for (const Run& run : runs)
        if (run.turning && run.renderer.starts_with("Earshot world")) worst = std::max({worst, run.l.high_db, run.r.high_db});
      if (worst > *require_bed_db) {
        std::printf("\nFAIL: a bed's or tier's turning-head ratio %.1f dB is above %.1f dB\n", worst, *require_bed_db);
        return 1;
      }
      std::printf("\nPASS: the beds' and tiers' turning-head ratios <= %.1f dB (worst %.1f)\n", *require_bed_db, worst);
    }
    if (require_db) {
      const Run& e = runs.front();  // Earshot, turning
      const double worst = std::max(e.l.high_db, e.r.high_db);
      if (worst > *require_db) {
        std::printf("\nFAIL: Earshot's turning-head ratio %.1f dB is above %.1f dB\n", worst, *require_db);
        return 1;
      }
      std::printf("\nPASS: Earshot's turning-head ratio %.1f dB <= %.1f dB\n", worst, *require_db);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "click_test: %s\n", e.what());
    return 2;
  }
  return 0;
}
