// How a simulation program's heap gives memory back: set once by DPMBase::run, before anything is
// allocated for the run (Documentation/performance.md, "Heap policy").
#pragma once

namespace pdpm {

/// With glibc: a block of 64 kB or more that the free heap cannot hold is mapped on its own (and
/// unmapped when freed) instead of growing the heap, and the top of the heap is returned once 64 kB
/// of it are free (no padding when it grows). glibc's defaults
/// raise both thresholds at run time (after the first large block is freed, up to 32 MB), so the
/// scratch of every neighbour-list rebuild and the start file's arrays stayed resident as free heap
/// between uses. A program that sets GLIBC_TUNABLES with malloc settings keeps its own; other C
/// libraries and the sanitizers' allocators are left alone. Returns whether the policy was set.
bool applyMemoryPolicy();

} // namespace pdpm
