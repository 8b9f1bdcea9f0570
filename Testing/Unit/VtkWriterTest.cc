// VTK snapshot output (Kernel/IO/VtkWriter.h): files are read back with VTK's own
// vtkXMLUnstructuredGridReader (through pdpm::readVtu, which wraps it, and directly when the VTK
// headers are visible to this target).
#include "Boundaries/PeriodicBox.h"
#include "Core/Error.h"
#include "IO/AtomicFile.h"
#include "IO/VtkWriter.h"
#include "Particles/ParticleData.h"
#include "Walls/Wall.h"

#include <gtest/gtest.h>

#include "TempDir.h"

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <unistd.h>
#include <vector>

#if __has_include(<vtkXMLUnstructuredGridReader.h>)
#define PDPM_TEST_HAVE_VTK_HEADERS 1
#include <vtkDataArray.h>
#include <vtkFieldData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>
#endif

namespace fs = std::filesystem;
using namespace pdpm;

namespace {

using pdpm::testing::TempDir;

/// A small scene: 4 particles in a box periodic along x only, a plane and a cylinder wall.
struct Scene {
    ParticleData p;
    PeriodicBox box;
    WallList walls;
    std::vector<int> coordination;
    std::vector<Vec3> force;

    Scene() {
        box.set({0, 0, 0}, {1, 2, 3}, true, false, false);
        p.add({0.1, 0.2, 0.3}, 0.05, 2500, 0, {1, 2, 3}, {0.1, 0.2, 0.3});
        p.add({1.3, 0.5, 0.5}, 0.06, 2500, 1, {-1, 0, 0.5});           // outside along periodic x
        p.add({-0.25, 2.5, 0.7}, 0.07, 1000, 0, {}, {0, 0, 7}, true);   // x wraps, y (not periodic) kept
        p.add({0.5, 1.0, 1.5}, 0.08, 1000, 2);
        coordination = {0, 2, 1, 3};
        force = {{0, 0, 0}, {3, 4, 0}, {0, 0, -2}, {1, 2, 2}};
        walls.push_back(std::make_unique<PlaneWall>(Vec3{0, 0, 0}, Vec3{0, 0, 1}, 1));
        walls.push_back(std::make_unique<CylinderWall>(Vec3{0.5, 1, 0}, Vec3{0, 0, 1}, 0.4, 2.0, 2));
    }
    SnapshotView view(double time, long step) const {
        return SnapshotView{p, coordination, force, walls, box, time, step};
    }
};

std::vector<std::string> listDir(const std::string& dir) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    return names;
}

const VtuArray& requireArray(const VtuArray* a, const std::string& name) {
    if (!a) throw std::runtime_error("missing array " + name);
    return *a;
}

void expectArray(const VtuContents& c, const std::string& name, const std::string& type, int components,
                 const std::vector<double>& values) {
    SCOPED_TRACE("point array " + name);
    const VtuArray* a = c.pointArray(name);
    ASSERT_NE(a, nullptr);
    EXPECT_EQ(a->type, type);
    EXPECT_EQ(a->components, components);
    ASSERT_EQ(a->values.size(), values.size());
    for (std::size_t k = 0; k < values.size(); ++k) EXPECT_DOUBLE_EQ(a->values[k], values[k]) << "value " << k;
}

std::vector<double> flat(const std::vector<Vec3>& v) {
    std::vector<double> out;
    for (const auto& x : v) {
        out.push_back(x.x);
        out.push_back(x.y);
        out.push_back(x.z);
    }
    return out;
}

} // namespace

TEST(VtkWriter, RegistersFactoryWhenHeaderIncluded) {
    EXPECT_TRUE(pdpmVtkWriterRegistered);
    ASSERT_TRUE(static_cast<bool>(snapshotWriterFactory()));
    auto w = snapshotWriterFactory()();
    ASSERT_NE(w, nullptr);
    EXPECT_NE(dynamic_cast<VtkSnapshotWriter*>(w.get()), nullptr);
    EXPECT_TRUE(registerVtkWriter());  // idempotent
}

TEST(VtkWriter, FileNamesArePaddedToFourDigits) {
    EXPECT_EQ(VtkSnapshotWriter::particleFileName("run", 0), "run_0000.vtu");
    EXPECT_EQ(VtkSnapshotWriter::particleFileName("run", 42), "run_0042.vtu");
    EXPECT_EQ(VtkSnapshotWriter::particleFileName("run", 12345), "run_12345.vtu");
    EXPECT_EQ(VtkSnapshotWriter::wallFileName("run", 7), "run_walls_0007.vtu");
    EXPECT_THROW(VtkSnapshotWriter::particleFileName("run", -1), InputError);
}

TEST(VtkWriter, WritesParticlesWallsAndCollection) {
    TempDir dir;
    Scene s;
    VtkSnapshotWriter writer;
    writer.write(dir.str(), "RUN", 0, s.view(0.0, 0));
    s.p.v[0] = {4, 5, 6};
    writer.write(dir.str(), "RUN", 1, s.view(0.25, 1000));

    // files present, no temporaries left
    for (const char* f : {"RUN_0000.vtu", "RUN_0001.vtu", "RUN_walls_0000.vtu", "RUN_walls_0001.vtu", "RUN.pvd"})
        EXPECT_TRUE(fs::exists(dir.file(f))) << f;
    for (const auto& name : listDir(dir.str())) EXPECT_EQ(name.find(".tmp"), std::string::npos) << name;
    EXPECT_EQ(listDir(dir.str()).size(), 5u);

    // XML header: binary appended (raw), the array types of the spec
    const std::string text = readWholeFile(dir.file("RUN_0001.vtu"));
    EXPECT_NE(text.find("type=\"UnstructuredGrid\""), std::string::npos);
    EXPECT_NE(text.find("format=\"appended\""), std::string::npos);
    EXPECT_NE(text.find("encoding=\"raw\""), std::string::npos);
    EXPECT_EQ(text.find("format=\"ascii\""), std::string::npos);
    EXPECT_EQ(text.find("compressor="), std::string::npos);
    EXPECT_NE(text.find("type=\"Int64\" Name=\"id\""), std::string::npos);
    EXPECT_NE(text.find("type=\"Int32\" Name=\"coordination\""), std::string::npos);

    const VtuContents c = readVtu(dir.file("RUN_0001.vtu"));
    const std::size_t n = s.p.size();
    ASSERT_EQ(c.points.size(), n);
    ASSERT_EQ(c.cellTypes.size(), n);
    for (std::size_t i = 0; i < n; ++i) {
        EXPECT_EQ(c.cellTypes[i], 1);  // VTK_VERTEX
        ASSERT_EQ(c.cells[i].size(), 1u);
        EXPECT_EQ(c.cells[i][0], static_cast<long long>(i));
    }
    // positions wrapped along x only
    const std::vector<Vec3> wrapped = {{0.1, 0.2, 0.3}, {0.3, 0.5, 0.5}, {0.75, 2.5, 0.7}, {0.5, 1.0, 1.5}};
    for (std::size_t i = 0; i < n; ++i) {
        EXPECT_NEAR(c.points[i].x, wrapped[i].x, 1e-12) << i;
        EXPECT_DOUBLE_EQ(c.points[i].y, wrapped[i].y) << i;
        EXPECT_DOUBLE_EQ(c.points[i].z, wrapped[i].z) << i;
        EXPECT_GE(c.points[i].x, 0.0);
        EXPECT_LT(c.points[i].x, 1.0);
    }
    EXPECT_EQ(s.p.x[1].x, 1.3);  // the particle data itself is not modified

    std::vector<double> fm;
    for (const auto& f : s.force) fm.push_back(norm(f));
    expectArray(c, "id", "Int64", 1, {0, 1, 2, 3});
    expectArray(c, "radius", "Float64", 1, s.p.r);
    expectArray(c, "mass", "Float64", 1, s.p.m);
    expectArray(c, "velocity", "Float64", 3, flat(s.p.v));
    expectArray(c, "angular_velocity", "Float64", 3, flat(s.p.w));
    expectArray(c, "species", "Int32", 1, {0, 1, 0, 2});
    expectArray(c, "fixed", "Int32", 1, {0, 0, 1, 0});
    expectArray(c, "coordination", "Int32", 1, {0, 2, 1, 3});
    expectArray(c, "force", "Float64", 3, flat(s.force));
    expectArray(c, "force_magnitude", "Float64", 1, fm);
    EXPECT_DOUBLE_EQ(c.pointArray("force_magnitude")->values[1], 5.0);
    EXPECT_DOUBLE_EQ(c.pointArray("velocity")->values[0], 4.0);  // second snapshot's value
    EXPECT_EQ(c.pointData.size(), 10u);

    const auto& time = requireArray(c.fieldArray("time"), "time");
    EXPECT_EQ(time.values, std::vector<double>{0.25});
    const auto& step = requireArray(c.fieldArray("step"), "step");
    EXPECT_EQ(step.values, std::vector<double>{1000});
    const auto& box = requireArray(c.fieldArray("box"), "box");
    EXPECT_EQ(box.values, (std::vector<double>{0, 1, 0, 2, 0, 3}));
    const auto& periodic = requireArray(c.fieldArray("periodic"), "periodic");
    EXPECT_EQ(periodic.values, (std::vector<double>{1, 0, 0}));
    EXPECT_DOUBLE_EQ(readVtu(dir.file("RUN_0000.vtu")).fieldArray("time")->values.at(0), 0.0);

    // walls: polygons for a plane (1 quad) and a cylinder
    const VtuContents w = readVtu(dir.file("RUN_walls_0001.vtu"));
    ASSERT_GT(w.cellTypes.size(), 1u);
    for (int t : w.cellTypes) EXPECT_EQ(t, 7);  // VTK_POLYGON
    WallMesh plane, cyl;
    s.walls[0]->mesh(s.box.lo(), s.box.hi(), plane);
    s.walls[1]->mesh(s.box.lo(), s.box.hi(), cyl);
    EXPECT_EQ(w.points.size(), plane.points.size() + cyl.points.size());
    EXPECT_EQ(w.cells.size(), plane.polygons.size() + cyl.polygons.size());
    ASSERT_FALSE(w.cells.empty());
    EXPECT_EQ(w.cells[0].size(), 4u);
    for (const auto& poly : w.cells)
        for (long long k : poly) EXPECT_LT(k, static_cast<long long>(w.points.size()));
    const VtuArray* wallIndex = w.cellArray("wall");
    ASSERT_NE(wallIndex, nullptr);
    EXPECT_EQ(wallIndex->values.front(), 0);
    EXPECT_EQ(wallIndex->values.back(), 1);
    for (const auto& p : cyl.points) EXPECT_NEAR(std::hypot(p.x - 0.5, p.y - 1), 0.4, 1e-12);

    // collection lists both snapshots with their times, walls as part 1
    const std::string pvd = readWholeFile(dir.file("RUN.pvd"));
    EXPECT_NE(pvd.find("type=\"Collection\""), std::string::npos);
    EXPECT_NE(pvd.find("<DataSet timestep=\"0\" group=\"\" part=\"0\" file=\"RUN_0000.vtu\"/>"), std::string::npos);
    EXPECT_NE(pvd.find("<DataSet timestep=\"0\" group=\"\" part=\"1\" file=\"RUN_walls_0000.vtu\"/>"), std::string::npos);
    EXPECT_NE(pvd.find("<DataSet timestep=\"0.25\" group=\"\" part=\"0\" file=\"RUN_0001.vtu\"/>"), std::string::npos);
    EXPECT_NE(pvd.find("<DataSet timestep=\"0.25\" group=\"\" part=\"1\" file=\"RUN_walls_0001.vtu\"/>"),
              std::string::npos);
    EXPECT_LT(pvd.find("RUN_0000.vtu"), pvd.find("RUN_0001.vtu"));
}

#ifdef PDPM_TEST_HAVE_VTK_HEADERS
TEST(VtkWriter, ReadableByVtkReaderDirectly) {
    TempDir dir;
    Scene s;
    VtkSnapshotWriter writer;
    writer.write(dir.str(), "RUN", 3, s.view(1.5, 7));
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->SetFileName(dir.file("RUN_0003.vtu").c_str());
    reader->Update();
    vtkUnstructuredGrid* g = reader->GetOutput();
    ASSERT_NE(g, nullptr);
    EXPECT_EQ(g->GetNumberOfPoints(), 4);
    EXPECT_EQ(g->GetNumberOfCells(), 4);
    vtkDataArray* r = g->GetPointData()->GetArray("radius");
    ASSERT_NE(r, nullptr);
    EXPECT_DOUBLE_EQ(r->GetComponent(2, 0), 0.07);
    vtkDataArray* v = g->GetPointData()->GetArray("velocity");
    ASSERT_NE(v, nullptr);
    EXPECT_EQ(v->GetNumberOfComponents(), 3);
    EXPECT_DOUBLE_EQ(v->GetComponent(1, 2), 0.5);
    vtkDataArray* t = g->GetFieldData()->GetArray("time");
    ASSERT_NE(t, nullptr);
    EXPECT_DOUBLE_EQ(t->GetComponent(0, 0), 1.5);
}
#endif

TEST(VtkWriter, ReadVtuParticlesRoundTrip) {
    TempDir dir;
    Scene s;
    VtkSnapshotWriter writer;
    writer.write(dir.str(), "sim", 0, s.view(0.125, 42));
    const VtuParticles r = readVtuParticles(dir.file("sim_0000.vtu"));
    ASSERT_EQ(r.size(), 4u);
    EXPECT_EQ(r.time, 0.125);
    EXPECT_EQ(r.step, 42);
    EXPECT_EQ(r.id, (std::vector<long long>{0, 1, 2, 3}));
    EXPECT_EQ(r.r, s.p.r);
    EXPECT_EQ(r.m, s.p.m);
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(r.v[i], s.p.v[i]);
        EXPECT_EQ(r.w[i], s.p.w[i]);
        EXPECT_EQ(r.force[i], s.force[i]);
    }
    EXPECT_NEAR(r.x[1].x, 0.3, 1e-12);
    EXPECT_EQ(r.species, (std::vector<int>{0, 1, 0, 2}));
    EXPECT_EQ(r.fixed, (std::vector<int>{0, 0, 1, 0}));
    EXPECT_EQ(r.coordination, s.coordination);
    EXPECT_EQ(r.boxLo, (Vec3{0, 0, 0}));
    EXPECT_EQ(r.boxHi, (Vec3{1, 2, 3}));
    EXPECT_TRUE(r.periodic[0]);
    EXPECT_FALSE(r.periodic[1]);
    EXPECT_FALSE(r.periodic[2]);
}

TEST(VtkWriter, NoWallsFileWithoutWalls) {
    TempDir dir;
    Scene s;
    s.walls.clear();
    VtkSnapshotWriter writer;
    writer.write(dir.str(), "RUN", 0, s.view(0, 0));
    EXPECT_TRUE(fs::exists(dir.file("RUN_0000.vtu")));
    EXPECT_FALSE(fs::exists(dir.file("RUN_walls_0000.vtu")));
    const std::string pvd = readWholeFile(dir.file("RUN.pvd"));
    EXPECT_NE(pvd.find("file=\"RUN_0000.vtu\""), std::string::npos);
    EXPECT_EQ(pvd.find("part=\"1\""), std::string::npos);
}

TEST(VtkWriter, EmptyParticleSet) {
    TempDir dir;
    Scene s;
    s.p.clear();
    s.coordination.clear();
    s.force.clear();
    VtkSnapshotWriter writer;
    writer.write(dir.str(), "RUN", 0, s.view(0, 0));
    const VtuParticles r = readVtuParticles(dir.file("RUN_0000.vtu"));
    EXPECT_EQ(r.size(), 0u);
}

TEST(VtkWriter, RestartedRunKeepsEarlierCollectionEntries) {
    TempDir dir;
    Scene s;
    {
        VtkSnapshotWriter first;
        first.write(dir.str(), "RUN", 0, s.view(0, 0));
        first.write(dir.str(), "RUN", 1, s.view(0.5, 10));
        first.write(dir.str(), "RUN", 2, s.view(1.0, 20));  // written after the restart file: superseded
    }
    {
        VtkSnapshotWriter restarted;  // restart from the state of snapshot 1
        restarted.write(dir.str(), "RUN", 2, s.view(1.25, 25));
        restarted.write(dir.str(), "RUN", 3, s.view(1.5, 30));
    }
    const std::string pvd = readWholeFile(dir.file("RUN.pvd"));
    for (const char* f : {"RUN_0000.vtu", "RUN_0001.vtu", "RUN_0002.vtu", "RUN_0003.vtu", "RUN_walls_0000.vtu",
                          "RUN_walls_0001.vtu", "RUN_walls_0002.vtu", "RUN_walls_0003.vtu"}) {
        const std::string attr = std::string("file=\"") + f + "\"";
        const auto pos = pvd.find(attr);
        ASSERT_NE(pos, std::string::npos) << f;
        EXPECT_EQ(pvd.find(attr, pos + 1), std::string::npos) << f << " listed twice";
    }
    EXPECT_NE(pvd.find("timestep=\"0.5\" group=\"\" part=\"0\" file=\"RUN_0001.vtu\""), std::string::npos);
    EXPECT_NE(pvd.find("timestep=\"1.25\" group=\"\" part=\"0\" file=\"RUN_0002.vtu\""), std::string::npos);
    EXPECT_EQ(pvd.find("timestep=\"1\""), std::string::npos);  // superseded entry gone
    EXPECT_EQ(readVtuParticles(dir.file("RUN_0002.vtu")).time, 1.25);

    // A fresh run from index 0 starts a new collection.
    VtkSnapshotWriter fresh;
    fresh.write(dir.str(), "RUN", 0, s.view(0, 0));
    const std::string pvd2 = readWholeFile(dir.file("RUN.pvd"));
    EXPECT_NE(pvd2.find("RUN_0000.vtu"), std::string::npos);
    EXPECT_EQ(pvd2.find("RUN_0001.vtu"), std::string::npos);
}

TEST(VtkWriter, WriteFailureIsInputErrorNamingTheFile) {
    TempDir dir;
    Scene s;
    // a directory in the way of the temporary file makes VTK fail to open it
    fs::create_directories(dir.file("RUN_0000.vtu.tmp"));
    VtkSnapshotWriter writer;
    try {
        writer.write(dir.str(), "RUN", 0, s.view(0, 0));
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("RUN_0000.vtu"), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(dir.file("RUN_0000.vtu")));
    EXPECT_FALSE(fs::exists(dir.file("RUN.pvd")));
}

TEST(VtkWriter, ReadingMissingOrForeignFileIsInputError) {
    TempDir dir;
    EXPECT_THROW(readVtuParticles(dir.file("nope.vtu")), InputError);
    EXPECT_THROW(readVtu(dir.file("nope.vtu")), InputError);
    writeWholeFile(dir.file("junk.vtu"), "this is not xml\n");
    try {
        readVtuParticles(dir.file("junk.vtu"));
        FAIL() << "expected InputError";
    } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("junk.vtu"), std::string::npos) << e.what();
    }
    // a valid .vtu without the particle arrays (a walls file)
    Scene s;
    VtkSnapshotWriter writer;
    writer.write(dir.str(), "RUN", 0, s.view(0, 0));
    EXPECT_THROW(readVtuParticles(dir.file("RUN_walls_0000.vtu")), InputError);
}
