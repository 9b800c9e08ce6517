// Guards of a robot segment against what other processes do to its file (layout.h: "What
// another process can do to a segment"; docs/architecture.md, the segment):
//
//   The mapping watch. A file truncated under its mappings makes every later access of a
//   page past the new end raise SIGBUS, which kills the process silently. The bridge installs
//   one SIGBUS handler (once, on the first segment mapped; the handler found before it is kept
//   and called for every fault outside a watched mapping). A fault inside a watched mapping
//   maps anonymous zero pages over the whole mapping (MAP_FIXED, the same protection), so the
//   faulting access completes, and sets the mapping's `lost` flag; the next check of either end
//   (CheckSegment, at least once a control cycle) reports kTruncated and the run ends with an
//   error, never with the signal. The check also compares the file's size (fstat on a
//   descriptor kept from set-up) with sizeof(Segment), so a truncation is seen before any page
//   faults, and a file truncated and grown again (zeros, no fault) is seen too.
//
//   The creator's clean-up. The segments a process created are unlinked by the creator on
//   every way out: the Producer's destructor (normal end, error paths, exceptions unwinding),
//   exit() without unwinding (an atexit hook), and the signals that end a process (SIGSEGV,
//   SIGBUS outside a segment, SIGFPE, SIGILL, SIGABRT, which an uncaught exception raises,
//   and SIGHUP, SIGQUIT, SIGINT, SIGTERM while the program has no handler of its own for
//   them: sim_host and hw_driver handle SIGINT/SIGTERM with a clean shutdown). The handlers
//   unlink, then let the signal act as before (the earlier handler, or the default action).
//   Only the creating process unlinks (a forked child does not), and only the file it created
//   (same device and inode: a segment created again under that name by another producer is
//   left alone). SIGKILL cannot be caught: the next producer replaces the stale segment.
//
// Everything used per cycle (MappingLost, FileSizeIs, LookAtSegment, CheckSegment) is real-time
// safe: no allocation, no exceptions, no logging; at most one fstat. The handlers use only
// async-signal-safe calls (mmap with MAP_FIXED, stat, unlink, sigaction, raise).
#pragma once

#include <sys/types.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "shm_bridge/bridge.h"
#include "shm_bridge/layout.h"

namespace ohrp::shm::internal {

//---------------- the mapping watch ----------------

// Watches the mapping [base, base + length) (writable: mapped read-write). Returns a slot for
// MappingLost and UnwatchMapping, or -1 when every slot is taken (the mapping is then not
// watched: a truncation ends the process with SIGBUS, as without the watch). Set-up only.
int WatchMapping(void* base, std::size_t length, bool writable);

// Stops watching (call it before the mapping is unmapped). Nothing for -1.
void UnwatchMapping(int slot);

// True once a SIGBUS inside the watched mapping was answered with zero pages.
bool MappingLost(int slot);

//---------------- the file ----------------

// A close-on-exec duplicate of `fd` (kept for fstat), or -1.
int KeepDescriptor(int fd);
void CloseDescriptor(int* fd);

// True when the file of `fd` has `size` bytes (false when fstat fails).
bool FileSizeIs(int fd, uint64_t size);

//---------------- the checks ----------------

// What a look at the mapped segment `s` of producer `producer_pid` finds, from memory only:
// kWakeUpWords when a wake-up word holds a value the bridge never writes, kHeader when the
// magic or the producer pid differ or the state is none a running segment holds (kRunning,
// kStopped, kFailed), else kNone.
SegmentFault LookAtSegment(const Segment& s, pid_t producer_pid);

// The per-cycle check of one end: kTruncated when the mapping is lost (`slot`) or the file of
// `fd` no longer has sizeof(Segment) bytes, else LookAtSegment. `fd` or `slot` -1: not checked.
SegmentFault CheckSegment(const Segment& s, pid_t producer_pid, int fd, int slot);

//---------------- the creator's clean-up ----------------

// Records that this process created the object `object_name` (under /dev/shm), open as `fd`,
// and installs the clean-up (above) the first time. Returns a slot for RemoveCreated, or -1
// when every slot is taken (the destructor still removes it). Set-up only.
int RegisterCreated(const std::string& object_name, int fd);

// Unlinks the object of `slot` when this process created it and the name still refers to it,
// and forgets the slot. Nothing for -1.
void RemoveCreated(int slot);

}  // namespace ohrp::shm::internal
