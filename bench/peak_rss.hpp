#pragma once
#include <sys/resource.h>

// Peak resident set size of this process so far, KiB (getrusage).
inline long peak_rss_kib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}
