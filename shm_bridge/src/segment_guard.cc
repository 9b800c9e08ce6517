// Guards of a robot segment: the SIGBUS mapping watch, the file checks and the creator's
// clean-up (segment_guard.h).
#include "segment_guard.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "signal_word.h"
#include "sync.h"

namespace ohrp::shm::internal {
namespace {

//---------------- tables shared with the signal handlers (lock-free reads) ----------------

constexpr int kMaxWatched = 32;  // mappings watched at once (a mapping per open end)
constexpr int kMaxCreated = 16;  // segments one process created and still owns
constexpr std::size_t kPathLen = 160;

struct Watched {
  std::atomic<uintptr_t> base{0};  // 0: free slot
  std::atomic<std::size_t> length{0};
  std::atomic<int> prot{0};
  std::atomic<int> lost{0};
};

struct Created {
  std::atomic<pid_t> creator{0};  // 0: free slot
  dev_t dev = 0;
  ino_t ino = 0;
  char path[kPathLen] = {};
};

Watched g_watched[kMaxWatched];
Created g_created[kMaxCreated];
std::mutex g_setup;  // set-up only: slot allocation and installing the handlers

// the handlers found before ours, called for what is not ours
struct sigaction g_previous_bus;
bool g_bus_installed = false;  // under g_setup
constexpr int kCleanUpSignals[] = {SIGSEGV, SIGFPE, SIGILL, SIGABRT,
                                   SIGHUP,  SIGQUIT, SIGINT, SIGTERM};
constexpr int kNumCleanUp = sizeof(kCleanUpSignals) / sizeof(kCleanUpSignals[0]);
struct sigaction g_previous[kNumCleanUp];
bool g_installed[kNumCleanUp] = {};
bool g_cleanup_installed = false;  // under g_setup

bool IsFault(int sig) { return sig == SIGSEGV || sig == SIGBUS || sig == SIGFPE || sig == SIGILL; }

// unlinks every segment this process created whose name still refers to it (async-signal-safe)
void UnlinkCreated() {
  const pid_t self = getpid();
  for (Created& c : g_created) {
    if (c.creator.load(std::memory_order_acquire) != self) continue;
    struct stat st;
    if (stat(c.path, &st) == 0 && st.st_dev == c.dev && st.st_ino == c.ino) unlink(c.path);
    c.creator.store(0, std::memory_order_release);
  }
}

// lets `sig` act as it would have without us: the earlier handler, or the default action
void Forward(int sig, siginfo_t* info, void* context, const struct sigaction& previous) {
  if ((previous.sa_flags & SA_SIGINFO) != 0) {
    if (previous.sa_sigaction != nullptr) previous.sa_sigaction(sig, info, context);
    return;
  }
  if (previous.sa_handler != SIG_DFL && previous.sa_handler != SIG_IGN) {
    previous.sa_handler(sig);
    return;
  }
  if (previous.sa_handler == SIG_IGN && !IsFault(sig)) return;
  // the default action: restored, then the fault repeats when the handler returns, or the
  // signal (blocked while its handler runs) is delivered again as it returns
  struct sigaction dfl {};
  dfl.sa_handler = SIG_DFL;
  sigemptyset(&dfl.sa_mask);
  sigaction(sig, &dfl, nullptr);
  if (!IsFault(sig)) raise(sig);
}

void OnBus(int sig, siginfo_t* info, void* context) {
  const uintptr_t addr = reinterpret_cast<uintptr_t>(info != nullptr ? info->si_addr : nullptr);
  for (Watched& w : g_watched) {
    const uintptr_t base = w.base.load(std::memory_order_acquire);
    const std::size_t length = w.length.load(std::memory_order_relaxed);
    if (base == 0 || addr < base || addr - base >= length) continue;
    // the file under the mapping is gone: zeros instead, so the access completes
    void* p = mmap(reinterpret_cast<void*>(base), length, w.prot.load(std::memory_order_relaxed),
                   MAP_FIXED | MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p != MAP_FAILED) {
      w.lost.store(1, std::memory_order_release);
      return;
    }
    break;
  }
  UnlinkCreated();
  Forward(sig, info, context, g_previous_bus);
}

void OnEndingSignal(int sig, siginfo_t* info, void* context) {
  UnlinkCreated();
  for (int i = 0; i < kNumCleanUp; ++i) {
    if (kCleanUpSignals[i] != sig) continue;
    sigaction(sig, &g_previous[i], nullptr);  // ours is done: the earlier one from now on
    Forward(sig, info, context, g_previous[i]);
    return;
  }
}

void InstallBusHandler() {  // under g_setup
  if (g_bus_installed) return;
  struct sigaction action {};
  action.sa_sigaction = OnBus;
  action.sa_flags = SA_SIGINFO | SA_ONSTACK;
  sigemptyset(&action.sa_mask);
  if (sigaction(SIGBUS, &action, &g_previous_bus) == 0) g_bus_installed = true;
}

void AtExit() { UnlinkCreated(); }

void InstallCleanUp() {  // under g_setup
  InstallBusHandler();
  if (g_cleanup_installed) return;
  g_cleanup_installed = true;
  std::atexit(AtExit);
  for (int i = 0; i < kNumCleanUp; ++i) {
    const int sig = kCleanUpSignals[i];
    struct sigaction current {};
    if (sigaction(sig, nullptr, &current) != 0) continue;
    // a program's own handler of a stop signal does a clean shutdown (the destructor removes
    // the segment); an ignored one is left ignored
    const bool own = (current.sa_flags & SA_SIGINFO) != 0 || current.sa_handler != SIG_DFL;
    if (!IsFault(sig) && sig != SIGABRT && own) continue;
    struct sigaction action {};
    action.sa_sigaction = OnEndingSignal;
    action.sa_flags = SA_SIGINFO | SA_ONSTACK;
    sigemptyset(&action.sa_mask);
    if (sigaction(sig, &action, &g_previous[i]) == 0) g_installed[i] = true;
  }
}

}  // namespace

//---------------- the mapping watch ----------------

int WatchMapping(void* base, std::size_t length, bool writable) {
  if (base == nullptr || length == 0) return -1;
  std::lock_guard<std::mutex> lock(g_setup);
  InstallBusHandler();
  for (int i = 0; i < kMaxWatched; ++i) {
    Watched& w = g_watched[i];
    if (w.base.load(std::memory_order_relaxed) != 0) continue;
    w.length.store(length, std::memory_order_relaxed);
    w.prot.store(writable ? PROT_READ | PROT_WRITE : PROT_READ, std::memory_order_relaxed);
    w.lost.store(0, std::memory_order_relaxed);
    w.base.store(reinterpret_cast<uintptr_t>(base), std::memory_order_release);
    return i;
  }
  return -1;
}

void UnwatchMapping(int slot) {
  if (slot < 0 || slot >= kMaxWatched) return;
  g_watched[slot].base.store(0, std::memory_order_release);
}

bool MappingLost(int slot) {
  if (slot < 0 || slot >= kMaxWatched) return false;
  return g_watched[slot].lost.load(std::memory_order_acquire) != 0;
}

//---------------- the file ----------------

int KeepDescriptor(int fd) { return fd < 0 ? -1 : fcntl(fd, F_DUPFD_CLOEXEC, 0); }

void CloseDescriptor(int* fd) {
  if (*fd >= 0) ::close(*fd);
  *fd = -1;
}

bool FileSizeIs(int fd, uint64_t size) {
  struct stat st;
  return fstat(fd, &st) == 0 && static_cast<uint64_t>(st.st_size) == size;
}

//---------------- the checks ----------------

SegmentFault LookAtSegment(const Segment& s, pid_t producer_pid) {
  auto& seg = const_cast<Segment&>(s);  // loads only (the observer's mapping is read-only)
  const uint32_t sensors = std::atomic_ref<uint32_t>(seg.sync.sensors_ready.word).load();
  const uint32_t commands = std::atomic_ref<uint32_t>(seg.sync.commands_ready.word).load();
  if (!ValidSignalWord(sensors) || !ValidSignalWord(commands)) return SegmentFault::kWakeUpWords;
  const uint32_t state = LoadState(seg.header);
  const pid_t pid = std::atomic_ref<int32_t>(seg.header.producer_pid).load();
  if (std::memcmp(s.header.magic, kMagic, sizeof(kMagic)) != 0 || pid != producer_pid ||
      !(state == static_cast<uint32_t>(ProducerState::kRunning) || IsEnded(state))) {
    return SegmentFault::kHeader;
  }
  return SegmentFault::kNone;
}

SegmentFault CheckSegment(const Segment& s, pid_t producer_pid, int fd, int slot) {
  // memory first: a truncation meanwhile makes these loads fault (then `lost` is set) or is
  // seen by the size just after
  const SegmentFault seen = LookAtSegment(s, producer_pid);
  if (MappingLost(slot) || (fd >= 0 && !FileSizeIs(fd, sizeof(Segment)))) {
    return SegmentFault::kTruncated;
  }
  return seen;
}

//---------------- the creator's clean-up ----------------

int RegisterCreated(const std::string& object_name, int fd) {
  struct stat st;
  if (fstat(fd, &st) != 0) return -1;
  const std::string path = "/dev/shm/" + object_name;
  if (path.size() >= kPathLen) return -1;
  std::lock_guard<std::mutex> lock(g_setup);
  InstallCleanUp();
  for (int i = 0; i < kMaxCreated; ++i) {
    Created& c = g_created[i];
    if (c.creator.load(std::memory_order_relaxed) != 0) continue;
    c.dev = st.st_dev;
    c.ino = st.st_ino;
    std::memcpy(c.path, path.c_str(), path.size() + 1);
    c.creator.store(getpid(), std::memory_order_release);
    return i;
  }
  return -1;
}

void RemoveCreated(int slot) {
  if (slot < 0 || slot >= kMaxCreated) return;
  Created& c = g_created[slot];
  if (c.creator.load(std::memory_order_acquire) != getpid()) return;  // a forked child's copy
  struct stat st;
  if (stat(c.path, &st) == 0 && st.st_dev == c.dev && st.st_ino == c.ino) unlink(c.path);
  c.creator.store(0, std::memory_order_release);
}

}  // namespace ohrp::shm::internal
