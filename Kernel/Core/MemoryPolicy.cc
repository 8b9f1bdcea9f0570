#include "Core/MemoryPolicy.h"

#include <cstdio>
#include <cstdlib>
#include <cstring>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace pdpm {

bool applyMemoryPolicy() {
#if defined(__GLIBC__) && !defined(__SANITIZE_ADDRESS__)
    const char* tunables = std::getenv("GLIBC_TUNABLES");
    if (tunables && std::strstr(tunables, "glibc.malloc.")) return false;  // the user's settings win
    constexpr int kThreshold = 64 * 1024;
    const bool ok = mallopt(M_MMAP_THRESHOLD, kThreshold) == 1 && mallopt(M_TRIM_THRESHOLD, kThreshold) == 1 &&
                    mallopt(M_TOP_PAD, 0) == 1;
    return ok;
#else
    return false;
#endif
}

} // namespace pdpm
