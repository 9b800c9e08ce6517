// The producers' output files (sim_host and hw_driver: --summary, --stats, the data log's
// folder), checked before anything runs and written whole with every error seen: a program never
// reports an output it could not write.
#pragma once

#include <cstdint>
#include <string>

namespace ohrp::model {

// The exit code of sim_host and hw_driver when a run could not write an output completely: the
// data log (a failed write: disk full, I/O error, file size limit) or the summary. The report
// names the file and the error. A run that failed for another reason keeps that reason's code
// (the log's failure is still in its report and summary).
inline constexpr int kExitOutputFailed = 9;

// Checks, before a program runs, that it can write the file `path`: creates it (or truncates an
// earlier one) and writes `provisional` into it with write(2), every result checked, so that a
// path in a missing folder, a directory, a read-only file system, a full disk or a file that
// takes no data (/proc/version, /dev/full) is refused with `*error` = "cannot write 'PATH':
// REASON". `provisional` should not be empty (an empty write proves nothing): e.g. a summary
// saying the run is under way, which the real summary replaces at the end (a reader of a run
// killed on the way sees that, never an earlier run's summary).
bool PrepareOutputFile(const std::string& path, const std::string& provisional,
                       std::string* error);

// Writes `text` as the whole content of `path` (created or truncated) with write(2), then
// fdatasync and close, each result checked. False with `*error` = "cannot write 'PATH': REASON".
bool WriteWholeFile(const std::string& path, const std::string& text, std::string* error);

// A size in bytes as given to --log-max: a whole number of bytes, or with a suffix k, M, G (or
// kB, MB, GB; powers of 1000) or KiB, MiB, GiB (powers of 1024), e.g. 500k, 20M, 1.5G. False
// with `*error` saying how to write it for anything else, zero or past 1 PB.
bool ParseByteSize(const std::string& text, uint64_t* bytes, std::string* error);

}  // namespace ohrp::model
