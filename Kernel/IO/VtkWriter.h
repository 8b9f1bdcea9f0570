// VTK XML output for ParaView (see Documentation/file-formats.md, "RUN.pvd and RUN_NNNN.vtu").
//
// Lives in the PowderDPMVTK library (the kernel library PowderDPM does not depend on VTK). Any
// program that includes this header gets VTK snapshots: the namespace-scope variable at the end
// registers VtkSnapshotWriter as pdpm::snapshotWriterFactory() during static initialisation (and,
// because it references registerVtkWriter(), pulls this object file out of the static library).
//
// This header does not include any VTK header, so users need not see VTK's include directories.
#pragma once
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "IO/SnapshotWriter.h"
#include "Math/Vec3.h"

namespace pdpm {

/// Writes, for snapshot index NNNN (zero-padded to at least 4 digits):
///   DIR/RUN_NNNN.vtu        particles: one VTK_VERTEX per particle, point and field data of the spec;
///   DIR/RUN_walls_NNNN.vtu  walls as polygons (only when there are walls);
///   DIR/RUN.pvd             collection of every snapshot written so far (rewritten each time).
/// Every file is written to NAME.tmp and renamed, so it appears complete or not at all. A write
/// failure throws InputError naming the file.
///
/// The first write() for a (dir, run) pair with index > 0 (a restarted run) keeps the DataSet
/// entries of an existing DIR/RUN.pvd with smaller indices, so the collection stays complete.
class VtkSnapshotWriter final : public SnapshotWriter {
public:
    void write(const std::string& dir, const std::string& run, int index, const SnapshotView& s) override;

    /// File names (without directory) used for snapshot `index`.
    static std::string particleFileName(const std::string& run, int index);
    static std::string wallFileName(const std::string& run, int index);

private:
    struct Entry {
        std::string timestep;      ///< text of the timestep attribute
        std::string particleFile;  ///< part 0, relative to the .pvd
        std::string wallFile;      ///< part 1, empty if there were no walls
    };
    void loadExistingCollection(const std::string& pvdPath, const std::string& run, int index);
    void writeCollection(const std::string& pvdPath) const;

    std::string key_;                 ///< dir + '\0' + run of the collection held in entries_
    bool loaded_ = false;
    std::map<int, Entry> entries_;    ///< by snapshot index
};

/// Sets snapshotWriterFactory() to make VtkSnapshotWriter objects. Idempotent; returns true.
bool registerVtkWriter();

/// Particles read back from a RUN_NNNN.vtu (vtkXMLUnstructuredGridReader). Arrays absent from
/// the file are left empty (id, radius, mass and velocity are required).
struct VtuParticles {
    std::vector<Vec3> x;             ///< point coordinates (wrapped positions)
    std::vector<Vec3> v;             ///< velocity
    std::vector<Vec3> w;             ///< angular_velocity
    std::vector<Vec3> force;         ///< force
    std::vector<double> r;           ///< radius
    std::vector<double> m;           ///< mass
    std::vector<double> forceMagnitude;  ///< force_magnitude
    std::vector<long long> id;
    std::vector<int> species;
    std::vector<int> fixed;
    std::vector<int> coordination;
    double time = 0;
    long long step = 0;
    Vec3 boxLo, boxHi;
    std::array<bool, 3> periodic{false, false, false};

    std::size_t size() const { return x.size(); }
};

/// Reads a particle .vtu written by VtkSnapshotWriter. InputError if the file is missing,
/// unreadable, or lacks the points or a required array.
VtuParticles readVtuParticles(const std::string& path);

/// Generic content of any .vtu file as VTK's reader sees it (tests, conversion tools).
struct VtuArray {
    std::string name;
    std::string type;          ///< VTK XML type name: "Float64", "Int32", "Int64", ...
    int components = 0;
    std::vector<double> values;  ///< tuples * components, row-major
    std::size_t tuples() const { return components > 0 ? values.size() / static_cast<std::size_t>(components) : 0; }
};
struct VtuContents {
    std::vector<Vec3> points;
    std::vector<int> cellTypes;                 ///< VTK cell type per cell (1 = VTK_VERTEX, 7 = VTK_POLYGON)
    std::vector<std::vector<long long>> cells;  ///< point indices per cell
    std::vector<VtuArray> pointData, cellData, fieldData;
    /// The array of that name, or nullptr.
    const VtuArray* pointArray(const std::string& name) const;
    const VtuArray* cellArray(const std::string& name) const;
    const VtuArray* fieldArray(const std::string& name) const;
};
/// InputError if the file is missing or VTK cannot read it.
VtuContents readVtu(const std::string& path);

} // namespace pdpm

/// Registration at static-initialisation time in every program that includes this header.
[[maybe_unused]] static const bool pdpmVtkWriterRegistered = pdpm::registerVtkWriter();
