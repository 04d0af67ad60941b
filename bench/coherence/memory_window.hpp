// Peak memory of one engine: VmHWM of /proc/self/status, reset before the engine starts.
#pragma once

namespace pleat::bench {

/// Frees memory to the system (malloc_trim), notes the resident set, then resets the peak to it
/// ("5" > /proc/self/clear_refs, Linux >= 4.0). Returns whether the reset worked.
bool start_memory_window(double& rss_before_mb);
/// A "VmHWM" / "VmRSS" line of /proc/self/status, in MB (NaN if absent).
double status_mb(const char* key);

}  // namespace pleat::bench
