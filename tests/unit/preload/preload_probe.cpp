// An OpenAL program that knows nothing of Earshot, run under
// earshot-openal-run --tracker osc:PORT by the test preload_probe: it sends
// the head poses to that port itself and renders on OpenAL Soft's loopback
// device (HRTF on), so it can check what the shim does where the real
// programs cannot reach:
//   1. a context current on this thread only (alcSetThreadContext, the
//      process-wide context stays none) follows the head: a mono source
//      ahead goes to the right ear when the head turns left;
//   2. alGetListenerfv gives back what the program set while the head is turned;
//   3. contexts destroyed and created while poses keep arriving (the
//      tracker thread must never touch a destroyed one), then a
//      process-wide context, follow the head the other way;
//   4. the head's offset is turned with the program's listener (p + P h):
//      the program looks along -x at a source 1 m away, the head moves 0.5 m
//      to the listener's right (world -z), so the source is heard on the left;
//   5. a device closed with its context still alive (OpenAL Soft destroys it).
// With "recenter" (under --recenter-after), the head stays turned left but
// the source comes back ahead once the recenter has happened.
// Exits 0 and says "probe ok", or 1 naming the step that failed.
// usage: preload_probe PORT [recenter]
#define AL_ALEXT_PROTOTYPES
#include <AL/al.h>
#include <AL/alc.h>
#include <AL/alext.h>
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <string>
#include <thread>
#include <vector>

namespace {

constexpr int kRate = 44100;
constexpr int kChunk = kRate / 20;  // 50 ms

[[noreturn]] void fail(const std::string& why) {
  std::fprintf(stderr, "preload_probe: %s\n", why.c_str());
  std::exit(1);
}

// /earshot/ypr YAW 0 0 (float32 arguments), to 127.0.0.1:port.
class PoseSender {
 public:
  explicit PoseSender(int port) : fd_(socket(AF_INET, SOCK_DGRAM, 0)) {
    if (fd_ < 0) fail("no UDP socket");
    addr_.sin_family = AF_INET;
    addr_.sin_port = htons(static_cast<std::uint16_t>(port));
    addr_.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  }
  ~PoseSender() { close(fd_); }
  PoseSender(const PoseSender&) = delete;
  PoseSender& operator=(const PoseSender&) = delete;

  void send_yaw(float yaw_deg) const { send("/earshot/ypr", {yaw_deg, 0.0f, 0.0f}); }

  void send(const char* address, std::initializer_list<float> args) const {
    std::vector<unsigned char> m;
    auto str = [&](const char* s) {
      const std::size_t n = std::strlen(s);
      m.insert(m.end(), s, s + n);
      m.resize(m.size() + 4 - n % 4, 0);
    };
    str(address);
    str((std::string(",") + std::string(args.size(), 'f')).c_str());
    for (float f : args) {
      std::uint32_t u;
      std::memcpy(&u, &f, 4);
      u = htonl(u);
      const auto* b = reinterpret_cast<const unsigned char*>(&u);
      m.insert(m.end(), b, b + 4);
    }
    (void)sendto(fd_, m.data(), m.size(), 0, reinterpret_cast<const sockaddr*>(&addr_), sizeof addr_);
  }

 private:
  int fd_;
  sockaddr_in addr_{};
};

struct Scene {
  ALCdevice* device = nullptr;
  ALCcontext* context = nullptr;
  ALuint buffer = 0, source = 0;
};

// A context on `device` with a looping mono noise source 1 m ahead, made
// current on this thread only or process-wide.
Scene make_scene(ALCdevice* device, bool thread_local_context) {
  Scene s;
  s.device = device;
  const ALCint attrs[] = {ALC_FORMAT_CHANNELS_SOFT, ALC_STEREO_SOFT, ALC_FORMAT_TYPE_SOFT, ALC_FLOAT_SOFT,
                          ALC_FREQUENCY, kRate, ALC_HRTF_SOFT, ALC_TRUE, 0};
  s.context = alcCreateContext(device, attrs);
  if (!s.context) fail("alcCreateContext failed");
  if (thread_local_context ? !alcSetThreadContext(s.context) : !alcMakeContextCurrent(s.context))
    fail("cannot make the context current");
  std::vector<float> noise(kRate);
  unsigned r = 7;
  for (float& v : noise) {
    r = r * 1664525u + 1013904223u;
    v = 0.3f * (static_cast<float>(r >> 8) / 8388608.0f - 1.0f);
  }
  alGenBuffers(1, &s.buffer);
  alBufferData(s.buffer, AL_FORMAT_MONO_FLOAT32, noise.data(), static_cast<ALsizei>(noise.size() * sizeof(float)),
               kRate);
  alGenSources(1, &s.source);
  alSourcei(s.source, AL_BUFFER, static_cast<ALint>(s.buffer));
  alSourcei(s.source, AL_LOOPING, AL_TRUE);
  alSource3f(s.source, AL_POSITION, 0, 0, -1);
  alSourcePlay(s.source);
  if (alGetError() != AL_NO_ERROR) fail("setting up the scene failed");
  return s;
}

void destroy_scene(Scene& s) {
  alDeleteSources(1, &s.source);
  alDeleteBuffers(1, &s.buffer);
  alcSetThreadContext(nullptr);
  alcMakeContextCurrent(nullptr);
  alcDestroyContext(s.context);
}

// Left minus right level of the next 50 ms, dB.
double ild(ALCdevice* device) {
  std::vector<float> x(2 * kChunk);
  alcRenderSamplesSOFT(device, x.data(), kChunk);
  double el = 1e-20, er = 1e-20;
  for (int i = 0; i < kChunk; ++i) {
    el += double(x[2 * i]) * x[2 * i];
    er += double(x[2 * i + 1]) * x[2 * i + 1];
  }
  return 10 * std::log10(el / er);
}

// Sends `yaw` and renders until the ILD passes `want` (sign: the side) or 3 s pass.
double turn_until(const PoseSender& poses, ALCdevice* device, float yaw, double want) {
  double last = 0;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(3);
  while (std::chrono::steady_clock::now() < end) {
    poses.send_yaw(yaw);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    last = ild(device);
    if (want < 0 ? last < want : last > want) return last;
  }
  fail("head yaw " + std::to_string(yaw) + ": ILD " + std::to_string(last) + " dB never passed " +
       std::to_string(want) + " dB: the listener did not follow the head");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 && !(argc == 3 && std::string(argv[2]) == "recenter")) fail("usage: preload_probe PORT [recenter]");
  const PoseSender poses(std::atoi(argv[1]));
  ALCdevice* device = alcLoopbackOpenDeviceSOFT(nullptr);
  if (!device) fail("no loopback device");

  // 1. Thread-local context, head straight (no pose yet): the source is ahead.
  Scene a = make_scene(device, true);
  if (alcGetCurrentContext() != a.context) fail("the thread context is not current");
  ALCint hrtf = 0;
  alcGetIntegerv(device, ALC_HRTF_STATUS_SOFT, 1, &hrtf);
  if (hrtf != ALC_HRTF_ENABLED_SOFT) fail("OpenAL Soft did not enable HRTF on the loopback device");
  const float set_position[3] = {0, 0, 0}, set_orientation[6] = {0, 0, -1, 0, 1, 0};
  alListenerfv(AL_POSITION, set_position);
  alListenerfv(AL_ORIENTATION, set_orientation);
  const double straight = ild(device);
  if (std::abs(straight) > 1) fail("head straight: ILD " + std::to_string(straight) + " dB, expected about 0");
  const double left = turn_until(poses, device, 60, -6);
  if (argc == 3) {  // recenter: the same pose keeps coming, the sound returns ahead
    double now = left;
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(4);
    while (std::chrono::steady_clock::now() < end && std::abs(now) > 1) {
      poses.send_yaw(60);
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      now = ild(device);
    }
    if (std::abs(now) > 1) fail("recenter: ILD " + std::to_string(now) + " dB, the turned head did not become neutral");
    std::printf("probe ok: head left %+.2f dB, after the recenter %+.2f dB\n", left, now);
    destroy_scene(a);
    alcCloseDevice(device);
    return 0;
  }

  // 2. The program reads back what it set, not the turned listener.
  float position[3], orientation[6];
  alGetListenerfv(AL_POSITION, position);
  alGetListenerfv(AL_ORIENTATION, orientation);
  if (std::memcmp(position, set_position, sizeof position) || std::memcmp(orientation, set_orientation, sizeof orientation))
    fail("alGetListenerfv does not give back what the program set");

  // 3. Contexts destroyed and made while poses keep arriving.
  for (int i = 0; i < 20; ++i) {
    poses.send_yaw(i % 2 ? 60.0f : -60.0f);
    destroy_scene(a);
    a = make_scene(device, i % 2 == 0);
    (void)ild(device);
  }
  destroy_scene(a);
  Scene b = make_scene(device, false);  // process-wide
  const double right = turn_until(poses, device, -60, 6);

  // 4. The head's offset in the program's listener frame.
  const float looking_left[6] = {-1, 0, 0, 0, 1, 0};
  alListenerfv(AL_ORIENTATION, looking_left);
  alSource3f(b.source, AL_POSITION, -1, 0, 0);
  double offset = 0;
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(3);
  while (std::chrono::steady_clock::now() < end && offset < 3) {
    poses.send("/earshot/pose/ypr", {0.5f, 0, 0, 0, 0, 0});
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    offset = ild(device);
  }
  if (offset < 3) fail("head 0.5 m right of a listener looking along -x: ILD " + std::to_string(offset) +
                       " dB, expected the source on the left (> +3 dB)");

  // 5. The device closed with its context alive; poses keep coming.
  alcMakeContextCurrent(nullptr);
  alcCloseDevice(device);
  for (int i = 0; i < 10; ++i) {
    poses.send_yaw(30);
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  (void)b;
  std::printf("probe ok: ILD straight %+.2f dB, head left %+.2f dB, head right %+.2f dB, head moved right %+.2f dB\n",
              straight, left, right, offset);
  return 0;
}
