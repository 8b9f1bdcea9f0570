// Interface of particle/wall snapshot writers. The kernel library does not depend on VTK: the VTK
// writer lives in the PowderDPMVTK library and registers itself when a program includes
// "IO/VtkWriter.h" (drivers do; benchmarks don't, to stay small).
#pragma once
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "Boundaries/PeriodicBox.h"
#include "Particles/ParticleData.h"
#include "Walls/Wall.h"

namespace pdpm {

struct SnapshotView {
    const ParticleData& particles;
    const std::vector<int>& coordination;   ///< contacts per particle
    const std::vector<Vec3>& contactForce;  ///< total contact force per particle
    const WallList& walls;
    const PeriodicBox& box;
    double time;
    long step;
};

class SnapshotWriter {
public:
    virtual ~SnapshotWriter() = default;
    /// Write `RUN_NNNN.vtu` (particles) and `RUN_walls_NNNN.vtu` into dir, and update `RUN.pvd`.
    virtual void write(const std::string& dir, const std::string& run, int index, const SnapshotView& s) = 0;
};

using SnapshotWriterFactory = std::function<std::unique_ptr<SnapshotWriter>()>;
/// Set by the VTK library at static-initialisation time; empty when VTK output is not linked.
SnapshotWriterFactory& snapshotWriterFactory();

} // namespace pdpm
