// Readers and writers of the kernel's output files used by the tools (Documentation/file-formats.md):
// RUN_NNNN.vtu (particles), RUN.pvd (list of .vtu), RUN.fstat (contacts). All readers throw
// pdpm::InputError with one line naming the file (and line) on missing or malformed input.
#pragma once
#include "Snapshot.h"

#include <string>
#include <vector>

namespace pdpm::tools {

/// True when the library was built with VTK (vtu reading, vtu/vti writing).
bool haveVtk();

ParticleSnapshot readVtu(const std::string& path);
/// Writes a .vtu exactly as documented (used by tests and in-situ drivers); atomic (tmp + rename).
void writeVtu(const std::string& path, const ParticleSnapshot& s);

/// The .vtu files listed in a .pvd collection, in order, with paths resolved relative to the .pvd.
std::vector<std::string> readPvd(const std::string& path);

/// All blocks of a .fstat file, in file order.
std::vector<ContactSnapshot> readFstat(const std::string& path);
/// Appends one block in the documented format to `os` (17 significant digits).
void writeFstatBlock(std::ostream& os, const ContactSnapshot& c);
/// Writes all blocks to a file, atomically.
void writeFstat(const std::string& path, const std::vector<ContactSnapshot>& blocks);

/// One instant: particles (may be empty when only contacts were given) and contacts (may be null).
struct Frame {
    bool hasParticles = false;
    bool hasContacts = false;
    ParticleSnapshot particles;
    ContactSnapshot contacts;
    double time() const { return hasParticles ? particles.time : contacts.time; }
};

/// Loads the given input paths (.vtu, .pvd, .fstat, in any mix) and pairs particle snapshots with
/// contact blocks by step number (or by time when steps are unknown). Frames are sorted by time.
/// Contact blocks without particles become contact-only frames, and vice versa.
std::vector<Frame> loadFrames(const std::vector<std::string>& paths);

} // namespace pdpm::tools
