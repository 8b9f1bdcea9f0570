#include "IO/VtkWriter.h"

#include "Core/Error.h"
#include "IO/AtomicFile.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkCommand.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkExecutive.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkSmartPointer.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <system_error>

namespace fs = std::filesystem;

namespace pdpm {

namespace {

// ---- VTK error capture ------------------------------------------------------------------------
// With an ErrorEvent observer attached, VTK hands its error messages to the observer instead of
// printing them, so that we can report them in one InputError line.
class ErrorCatcher : public vtkCommand {
public:
    static ErrorCatcher* New() { return new ErrorCatcher; }
    void Execute(vtkObject*, unsigned long, void* callData) override {
        ++count;
        const std::string text = callData ? static_cast<const char*>(callData) : "";
        // Pipeline failures only repeat that the algorithm failed; keep them only if nothing else came.
        const bool pipeline = text.find("returned failure for request") != std::string::npos;
        const std::string line = essentialLine(text);
        if (line.empty() || (pipeline && !message.empty())) return;
        if (pipeline) {
            if (message.empty()) message = "VTK pipeline failed";
            return;
        }
        if (message == "VTK pipeline failed") message.clear();
        if (!message.empty()) message += "; ";
        message += line;
    }
    /// The first line of a VTK message that is not "ERROR: In FILE, line N", without the
    /// "vtkClass (0x...): " prefix.
    static std::string essentialLine(const std::string& text) {
        std::size_t start = 0;
        while (start < text.size()) {
            std::size_t end = text.find('\n', start);
            if (end == std::string::npos) end = text.size();
            std::string line = text.substr(start, end - start);
            start = end + 1;
            while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
            if (line.empty() || line.rfind("ERROR: In ", 0) == 0) continue;
            const std::size_t sep = line.find("): ");
            if (line.rfind("vtk", 0) == 0 && sep != std::string::npos) line = line.substr(sep + 3);
            return line;
        }
        return {};
    }
    int count = 0;
    std::string message;
};

std::string joinPath(const std::string& dir, const std::string& name) {
    if (dir.empty()) return name;
    return (fs::path(dir) / name).string();
}

void removeQuietly(const std::string& p) {
    std::error_code ec;
    fs::remove(p, ec);
}

std::string indexText(int index) {
    if (index < 0) throw InputError("VTK output: negative snapshot index " + std::to_string(index));
    char buf[32];
    std::snprintf(buf, sizeof buf, "%04d", index);
    return buf;
}

std::string timeText(double t) {
    if (!std::isfinite(t)) return "0";
    char buf[64];
    const auto res = std::to_chars(buf, buf + sizeof buf, t);
    return std::string(buf, res.ptr);
}

std::string xmlEscape(const std::string& s) {
    std::string out;
    for (char c : s) {
        switch (c) {
        case '&': out += "&amp;"; break;
        case '<': out += "&lt;"; break;
        case '>': out += "&gt;"; break;
        case '"': out += "&quot;"; break;
        case '\'': out += "&apos;"; break;
        default: out += c;
        }
    }
    return out;
}

std::string xmlUnescape(const std::string& s) {
    static const std::pair<const char*, char> table[] = {
        {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
    std::string out;
    for (std::size_t i = 0; i < s.size();) {
        bool done = false;
        if (s[i] == '&') {
            for (const auto& [ent, ch] : table) {
                const std::size_t len = std::char_traits<char>::length(ent);
                if (s.compare(i, len, ent) == 0) {
                    out += ch;
                    i += len;
                    done = true;
                    break;
                }
            }
        }
        if (!done) out += s[i++];
    }
    return out;
}

/// Value of attribute `name` inside one XML tag text, false if absent.
bool xmlAttribute(const std::string& tag, const std::string& name, std::string& value) {
    std::size_t pos = 0;
    while ((pos = tag.find(name, pos)) != std::string::npos) {
        const bool startOk = pos > 0 && (tag[pos - 1] == ' ' || tag[pos - 1] == '\t' || tag[pos - 1] == '\n' ||
                                         tag[pos - 1] == '\r');
        std::size_t p = pos + name.size();
        while (p < tag.size() && (tag[p] == ' ' || tag[p] == '\t')) ++p;
        if (startOk && p < tag.size() && tag[p] == '=') {
            ++p;
            while (p < tag.size() && (tag[p] == ' ' || tag[p] == '\t')) ++p;
            if (p < tag.size() && (tag[p] == '"' || tag[p] == '\'')) {
                const char q = tag[p];
                const std::size_t end = tag.find(q, p + 1);
                if (end == std::string::npos) return false;
                value = xmlUnescape(tag.substr(p + 1, end - p - 1));
                return true;
            }
        }
        pos += name.size();
    }
    return false;
}

/// Snapshot index encoded in `file` = prefix + digits + ".vtu", or -1.
long long indexFromFileName(const std::string& file, const std::string& prefix) {
    const std::string suffix = ".vtu";
    if (file.size() <= prefix.size() + suffix.size()) return -1;
    if (file.compare(0, prefix.size(), prefix) != 0) return -1;
    if (file.compare(file.size() - suffix.size(), suffix.size(), suffix) != 0) return -1;
    const std::string digits = file.substr(prefix.size(), file.size() - prefix.size() - suffix.size());
    if (digits.empty() || digits.size() > 9) return -1;
    long long v = 0;
    for (char c : digits) {
        if (c < '0' || c > '9') return -1;
        v = 10 * v + (c - '0');
    }
    return v;
}

/// Writes `grid` to `path` through `path.tmp` and a rename. InputError naming the file on failure.
void writeGridAtomically(vtkUnstructuredGrid* grid, const std::string& path) {
    const std::string tmp = path + ".tmp";
    vtkNew<ErrorCatcher> errors;
    vtkNew<vtkXMLUnstructuredGridWriter> writer;
    writer->AddObserver(vtkCommand::ErrorEvent, errors);
    writer->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    writer->SetInputData(grid);
    writer->SetFileName(tmp.c_str());
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();  // raw binary appended data
    writer->SetCompressorTypeToNone();
    writer->SetHeaderTypeToUInt64();
    const int ok = writer->Write();
    if (!ok || writer->GetErrorCode() != 0 || errors->count > 0 || !fs::exists(tmp)) {
        removeQuietly(tmp);
        std::string why = errors->message;
        if (why.empty() && writer->GetErrorCode() != 0) why = "error code " + std::to_string(writer->GetErrorCode());
        if (why.empty()) why = "VTK writer failed";
        throw InputError("cannot write '" + path + "': " + why);
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
        removeQuietly(tmp);
        throw InputError("cannot write '" + path + "': rename failed: " + ec.message());
    }
}

template <class Array>
vtkSmartPointer<Array> makeArray(const char* name, int components, vtkIdType tuples) {
    auto a = vtkSmartPointer<Array>::New();
    a->SetName(name);
    a->SetNumberOfComponents(components);
    a->SetNumberOfTuples(tuples);
    return a;
}

vtkSmartPointer<vtkDoubleArray> vec3Array(const char* name, const std::vector<Vec3>& src, std::size_t n) {
    auto a = makeArray<vtkDoubleArray>(name, 3, static_cast<vtkIdType>(n));
    double* p = a->GetPointer(0);
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 v = i < src.size() ? src[i] : Vec3{};
        p[3 * i] = v.x;
        p[3 * i + 1] = v.y;
        p[3 * i + 2] = v.z;
    }
    return a;
}

void checkSize(std::size_t have, std::size_t n, const char* what) {
    if (have != n)
        throw std::invalid_argument(std::string("VtkSnapshotWriter: ") + what + " has " + std::to_string(have) +
                                    " entries for " + std::to_string(n) + " particles");
}

vtkSmartPointer<vtkUnstructuredGrid> particleGrid(const SnapshotView& s) {
    const ParticleData& P = s.particles;
    const std::size_t n = P.size();
    checkSize(P.r.size(), n, "radius");
    checkSize(P.m.size(), n, "mass");
    checkSize(P.v.size(), n, "velocity");
    checkSize(P.w.size(), n, "angular velocity");
    checkSize(P.species.size(), n, "species");
    checkSize(P.fixed.size(), n, "fixed");
    checkSize(s.coordination.size(), n, "coordination");
    checkSize(s.contactForce.size(), n, "contact force");
    const auto N = static_cast<vtkIdType>(n);

    auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();

    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(N);
    // wrapped as the next neighbour-list build would: across a wall-driven boundary the velocity too
    std::vector<Vec3> velocity(P.v.begin(), P.v.begin() + static_cast<std::ptrdiff_t>(n));
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 x = P.x[i];
        velocity[i] += s.box.wrapWithVelocityShift(x);
        points->SetPoint(static_cast<vtkIdType>(i), x.x, x.y, x.z);
    }
    grid->SetPoints(points);

    // one VTK_VERTEX per particle
    vtkNew<vtkIdTypeArray> offsets, connectivity;
    offsets->SetNumberOfValues(N + 1);
    connectivity->SetNumberOfValues(N);
    for (vtkIdType i = 0; i <= N; ++i) offsets->SetValue(i, i);
    for (vtkIdType i = 0; i < N; ++i) connectivity->SetValue(i, i);
    vtkNew<vtkCellArray> cells;
    cells->SetData(offsets, connectivity);
    grid->SetCells(VTK_VERTEX, cells);

    vtkPointData* pd = grid->GetPointData();
    auto id = makeArray<vtkTypeInt64Array>("id", 1, N);
    auto radius = makeArray<vtkDoubleArray>("radius", 1, N);
    auto mass = makeArray<vtkDoubleArray>("mass", 1, N);
    auto species = makeArray<vtkTypeInt32Array>("species", 1, N);
    auto fixed = makeArray<vtkTypeInt32Array>("fixed", 1, N);
    auto coordination = makeArray<vtkTypeInt32Array>("coordination", 1, N);
    auto forceMagnitude = makeArray<vtkDoubleArray>("force_magnitude", 1, N);
    for (std::size_t i = 0; i < n; ++i) {
        const auto k = static_cast<vtkIdType>(i);
        id->SetValue(k, static_cast<vtkTypeInt64>(i));
        radius->SetValue(k, P.r[i]);
        mass->SetValue(k, P.m[i]);
        species->SetValue(k, P.species[i]);
        fixed->SetValue(k, P.fixed[i] ? 1 : 0);
        coordination->SetValue(k, s.coordination[i]);
        forceMagnitude->SetValue(k, norm(s.contactForce[i]));
    }
    pd->AddArray(id);
    pd->AddArray(radius);
    pd->AddArray(mass);
    pd->AddArray(vec3Array("velocity", velocity, n));
    pd->AddArray(vec3Array("angular_velocity", P.w, n));
    pd->AddArray(species);
    pd->AddArray(fixed);
    pd->AddArray(coordination);
    pd->AddArray(vec3Array("force", s.contactForce, n));
    pd->AddArray(forceMagnitude);

    vtkFieldData* fd = grid->GetFieldData();
    auto time = makeArray<vtkDoubleArray>("time", 1, 1);
    time->SetValue(0, s.time);
    auto step = makeArray<vtkTypeInt64Array>("step", 1, 1);
    step->SetValue(0, static_cast<vtkTypeInt64>(s.step));
    auto box = makeArray<vtkDoubleArray>("box", 6, 1);
    const Vec3 &lo = s.box.lo(), &hi = s.box.hi();
    const double b[6] = {lo.x, hi.x, lo.y, hi.y, lo.z, hi.z};
    for (int c = 0; c < 6; ++c) box->SetValue(c, b[c]);
    auto periodic = makeArray<vtkTypeInt32Array>("periodic", 3, 1);
    for (int a = 0; a < 3; ++a) periodic->SetValue(a, s.box.periodic(a) ? 1 : 0);
    fd->AddArray(time);
    fd->AddArray(step);
    fd->AddArray(box);
    fd->AddArray(periodic);
    return grid;
}

vtkSmartPointer<vtkUnstructuredGrid> wallGrid(const SnapshotView& s) {
    auto grid = vtkSmartPointer<vtkUnstructuredGrid>::New();
    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    vtkNew<vtkCellArray> cells;
    vtkNew<vtkTypeInt32Array> wallIndex, wallSpecies;
    wallIndex->SetName("wall");
    wallSpecies->SetName("species");
    for (std::size_t w = 0; w < s.walls.size(); ++w) {
        if (!s.walls[w]) continue;
        WallMesh mesh;
        s.walls[w]->mesh(s.box.lo(), s.box.hi(), mesh);
        const vtkIdType base = points->GetNumberOfPoints();
        for (const Vec3& p : mesh.points) points->InsertNextPoint(p.x, p.y, p.z);
        for (const auto& poly : mesh.polygons) {
            if (poly.size() < 3) continue;
            std::vector<vtkIdType> ids;
            ids.reserve(poly.size());
            for (int k : poly) {
                if (k < 0 || static_cast<std::size_t>(k) >= mesh.points.size())
                    throw std::logic_error("wall mesh: polygon refers to a missing point");
                ids.push_back(base + k);
            }
            cells->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
            wallIndex->InsertNextValue(static_cast<int>(w));
            wallSpecies->InsertNextValue(s.walls[w]->species);
        }
    }
    grid->SetPoints(points);
    grid->SetCells(VTK_POLYGON, cells);
    grid->GetCellData()->AddArray(wallIndex);
    grid->GetCellData()->AddArray(wallSpecies);
    auto time = makeArray<vtkDoubleArray>("time", 1, 1);
    time->SetValue(0, s.time);
    auto step = makeArray<vtkTypeInt64Array>("step", 1, 1);
    step->SetValue(0, static_cast<vtkTypeInt64>(s.step));
    grid->GetFieldData()->AddArray(time);
    grid->GetFieldData()->AddArray(step);
    return grid;
}

} // namespace

// ---- VtkSnapshotWriter ---------------------------------------------------------------------------
std::string VtkSnapshotWriter::particleFileName(const std::string& run, int index) {
    return run + "_" + indexText(index) + ".vtu";
}

std::string VtkSnapshotWriter::wallFileName(const std::string& run, int index) {
    return run + "_walls_" + indexText(index) + ".vtu";
}

void VtkSnapshotWriter::loadExistingCollection(const std::string& pvdPath, const std::string& run, int index) {
    std::error_code ec;
    if (!fs::exists(pvdPath, ec)) return;
    const std::string text = readWholeFile(pvdPath);
    const std::string particlePrefix = run + "_", wallPrefix = run + "_walls_";
    std::size_t pos = 0;
    while ((pos = text.find("<DataSet", pos)) != std::string::npos) {
        const std::size_t end = text.find('>', pos);
        if (end == std::string::npos) break;
        const std::string tag = text.substr(pos, end - pos);
        pos = end;
        std::string file, timestep, part;
        if (!xmlAttribute(tag, "file", file) || !xmlAttribute(tag, "timestep", timestep)) continue;
        // A file name like RUN_walls_0003.vtu also starts with "RUN_": test the wall prefix first.
        long long k = indexFromFileName(file, wallPrefix);
        const bool isWall = k >= 0;
        if (!isWall) k = indexFromFileName(file, particlePrefix);
        if (k < 0 || k >= index) continue;
        Entry& e = entries_[static_cast<int>(k)];
        if (isWall) e.wallFile = file;
        else e.particleFile = file;
        if (e.timestep.empty() || !isWall) e.timestep = timestep;
    }
    // an entry needs its particle file
    for (auto it = entries_.begin(); it != entries_.end();) {
        if (it->second.particleFile.empty()) it = entries_.erase(it);
        else ++it;
    }
}

void VtkSnapshotWriter::writeCollection(const std::string& pvdPath) const {
    std::ostringstream os;
    os << "<?xml version=\"1.0\"?>\n"
       << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
       << "  <Collection>\n";
    for (const auto& [index, e] : entries_) {
        os << "    <DataSet timestep=\"" << xmlEscape(e.timestep) << "\" group=\"\" part=\"0\" file=\""
           << xmlEscape(e.particleFile) << "\"/>\n";
        if (!e.wallFile.empty())
            os << "    <DataSet timestep=\"" << xmlEscape(e.timestep) << "\" group=\"\" part=\"1\" file=\""
               << xmlEscape(e.wallFile) << "\"/>\n";
    }
    os << "  </Collection>\n"
       << "</VTKFile>\n";
    writeWholeFile(pvdPath, os.str());
}

void VtkSnapshotWriter::write(const std::string& dir, const std::string& run, int index, const SnapshotView& s) {
    if (run.empty()) throw InputError("VTK output: empty run name");
    const std::string particleName = particleFileName(run, index);  // checks index >= 0
    const std::string wallName = wallFileName(run, index);
    if (!dir.empty()) ensureDirectory(dir);
    const std::string pvdPath = joinPath(dir, run + ".pvd");

    const std::string key = dir + '\0' + run;
    if (!loaded_ || key != key_) {
        entries_.clear();
        key_ = key;
        loaded_ = true;
        if (index > 0) loadExistingCollection(pvdPath, run, index);
    }
    // A snapshot supersedes any stale later ones (the collection lists a consistent history).
    entries_.erase(entries_.lower_bound(index), entries_.end());

    writeGridAtomically(particleGrid(s), joinPath(dir, particleName));

    bool haveWalls = false;
    for (const auto& w : s.walls) haveWalls = haveWalls || static_cast<bool>(w);
    if (haveWalls) {
        writeGridAtomically(wallGrid(s), joinPath(dir, wallName));
    } else {
        removeQuietly(joinPath(dir, wallName));  // stale file from an earlier run with walls
    }

    Entry& e = entries_[index];
    e.timestep = timeText(s.time);
    e.particleFile = particleName;
    e.wallFile = haveWalls ? wallName : std::string();
    writeCollection(pvdPath);
}

bool registerVtkWriter() {
    static const bool done = [] {
        snapshotWriterFactory() = [] { return std::unique_ptr<SnapshotWriter>(new VtkSnapshotWriter); };
        return true;
    }();
    return done;
}

// ---- reading -------------------------------------------------------------------------------------
namespace {

std::string xmlTypeName(vtkDataArray* a) {
    const int t = a->GetDataType();
    const int bits = 8 * a->GetDataTypeSize();
    if (t == VTK_FLOAT || t == VTK_DOUBLE) return "Float" + std::to_string(bits);
    const bool isSigned = a->GetDataTypeMin() < 0;
    return (isSigned ? "Int" : "UInt") + std::to_string(bits);
}

VtuArray copyArray(vtkDataArray* a) {
    VtuArray out;
    out.name = a->GetName() ? a->GetName() : "";
    out.type = xmlTypeName(a);
    out.components = a->GetNumberOfComponents();
    const vtkIdType nt = a->GetNumberOfTuples();
    out.values.resize(static_cast<std::size_t>(nt) * static_cast<std::size_t>(out.components));
    for (vtkIdType i = 0; i < nt; ++i)
        for (int c = 0; c < out.components; ++c)
            out.values[static_cast<std::size_t>(i) * out.components + c] = a->GetComponent(i, c);
    return out;
}

void copyArrays(vtkFieldData* fd, std::vector<VtuArray>& out) {
    if (!fd) return;
    for (int k = 0; k < fd->GetNumberOfArrays(); ++k)
        if (vtkDataArray* a = fd->GetArray(k)) out.push_back(copyArray(a));
}

/// Reads `path` with vtkXMLUnstructuredGridReader; InputError naming the file on any failure.
vtkSmartPointer<vtkUnstructuredGrid> readGrid(const std::string& path) {
    std::error_code ec;
    if (!fs::is_regular_file(path, ec)) throw InputError("cannot read '" + path + "': no such file");
    vtkNew<ErrorCatcher> errors;
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    reader->AddObserver(vtkCommand::ErrorEvent, errors);
    reader->GetExecutive()->AddObserver(vtkCommand::ErrorEvent, errors);
    reader->SetReaderErrorObserver(errors);
    reader->SetParserErrorObserver(errors);
    if (!reader->CanReadFile(path.c_str()))
        throw InputError("cannot read '" + path + "': not a VTK XML UnstructuredGrid file");
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkUnstructuredGrid* grid = reader->GetOutput();
    if (errors->count > 0 || reader->GetErrorCode() != 0 || !grid)
        throw InputError("cannot read '" + path + "': " +
                         (errors->message.empty() ? std::string("VTK reader failed") : errors->message));
    auto result = vtkSmartPointer<vtkUnstructuredGrid>::New();
    result->ShallowCopy(grid);
    return result;
}

const VtuArray* findArray(const std::vector<VtuArray>& v, const std::string& name) {
    for (const auto& a : v)
        if (a.name == name) return &a;
    return nullptr;
}

} // namespace

const VtuArray* VtuContents::pointArray(const std::string& name) const { return findArray(pointData, name); }
const VtuArray* VtuContents::cellArray(const std::string& name) const { return findArray(cellData, name); }
const VtuArray* VtuContents::fieldArray(const std::string& name) const { return findArray(fieldData, name); }

VtuContents readVtu(const std::string& path) {
    const auto grid = readGrid(path);
    VtuContents out;
    if (vtkPoints* pts = grid->GetPoints()) {
        out.points.resize(static_cast<std::size_t>(pts->GetNumberOfPoints()));
        for (vtkIdType i = 0; i < pts->GetNumberOfPoints(); ++i) {
            double p[3];
            pts->GetPoint(i, p);
            out.points[static_cast<std::size_t>(i)] = {p[0], p[1], p[2]};
        }
    }
    const vtkIdType nc = grid->GetNumberOfCells();
    out.cellTypes.resize(static_cast<std::size_t>(nc));
    out.cells.resize(static_cast<std::size_t>(nc));
    for (vtkIdType c = 0; c < nc; ++c) {
        out.cellTypes[static_cast<std::size_t>(c)] = grid->GetCellType(c);
        vtkIdType npts = 0;
        const vtkIdType* ids = nullptr;
        grid->GetCellPoints(c, npts, ids);
        out.cells[static_cast<std::size_t>(c)].assign(ids, ids + npts);
    }
    copyArrays(grid->GetPointData(), out.pointData);
    copyArrays(grid->GetCellData(), out.cellData);
    copyArrays(grid->GetFieldData(), out.fieldData);
    return out;
}

VtuParticles readVtuParticles(const std::string& path) {
    const auto grid = readGrid(path);
    VtuParticles out;
    vtkPoints* pts = grid->GetPoints();
    if (!pts) throw InputError("cannot read '" + path + "': no points");
    const vtkIdType n = pts->GetNumberOfPoints();
    const auto N = static_cast<std::size_t>(n);
    out.x.resize(N);
    for (vtkIdType i = 0; i < n; ++i) {
        double p[3];
        pts->GetPoint(i, p);
        out.x[static_cast<std::size_t>(i)] = {p[0], p[1], p[2]};
    }

    vtkPointData* pd = grid->GetPointData();
    auto array = [&](const char* name, int components, bool required) -> vtkDataArray* {
        vtkDataArray* a = pd ? pd->GetArray(name) : nullptr;
        if (!a) {
            if (required) throw InputError("cannot read '" + path + "': no point array '" + name + "'");
            return nullptr;
        }
        if (a->GetNumberOfComponents() != components || a->GetNumberOfTuples() != n)
            throw InputError("cannot read '" + path + "': point array '" + name + "' has " +
                             std::to_string(a->GetNumberOfComponents()) + " components and " +
                             std::to_string(a->GetNumberOfTuples()) + " tuples (expected " +
                             std::to_string(components) + " and " + std::to_string(n) + ")");
        return a;
    };
    auto vec3 = [&](const char* name, bool required, std::vector<Vec3>& dst) {
        if (vtkDataArray* a = array(name, 3, required)) {
            dst.resize(N);
            for (vtkIdType i = 0; i < n; ++i)
                dst[static_cast<std::size_t>(i)] = {a->GetComponent(i, 0), a->GetComponent(i, 1), a->GetComponent(i, 2)};
        }
    };
    auto scalar = [&](const char* name, bool required, auto& dst) {
        if (vtkDataArray* a = array(name, 1, required)) {
            using T = typename std::decay_t<decltype(dst)>::value_type;
            dst.resize(N);
            for (vtkIdType i = 0; i < n; ++i) dst[static_cast<std::size_t>(i)] = static_cast<T>(a->GetComponent(i, 0));
        }
    };
    scalar("id", true, out.id);
    scalar("radius", true, out.r);
    scalar("mass", true, out.m);
    vec3("velocity", true, out.v);
    vec3("angular_velocity", false, out.w);
    vec3("force", false, out.force);
    scalar("force_magnitude", false, out.forceMagnitude);
    scalar("species", false, out.species);
    scalar("fixed", false, out.fixed);
    scalar("coordination", false, out.coordination);

    vtkFieldData* fd = grid->GetFieldData();
    auto field = [&](const char* name, int count) -> vtkDataArray* {
        vtkDataArray* a = fd ? fd->GetArray(name) : nullptr;
        if (!a) return nullptr;
        if (a->GetNumberOfTuples() * a->GetNumberOfComponents() != count)
            throw InputError("cannot read '" + path + "': field data '" + name + "' should have " +
                             std::to_string(count) + " values");
        return a;
    };
    // flat value k of a field array (tuples * components)
    auto value = [](vtkDataArray* a, int k) {
        const int nc = a->GetNumberOfComponents();
        return a->GetComponent(k / nc, k % nc);
    };
    if (vtkDataArray* a = field("time", 1)) out.time = value(a, 0);
    if (vtkDataArray* a = field("step", 1)) out.step = static_cast<long long>(value(a, 0));
    if (vtkDataArray* a = field("box", 6)) {
        for (int d = 0; d < 3; ++d) {
            out.boxLo[d] = value(a, 2 * d);
            out.boxHi[d] = value(a, 2 * d + 1);
        }
    }
    if (vtkDataArray* a = field("periodic", 3))
        for (int d = 0; d < 3; ++d) out.periodic[d] = value(a, d) != 0;
    return out;
}

} // namespace pdpm
