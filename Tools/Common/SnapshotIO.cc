#include "SnapshotIO.h"

#include "Core/Error.h"
#include "Core/Parameters.h"
#include "OutputFiles.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <regex>
#include <sstream>

#ifdef PDPM_TOOLS_HAVE_VTK
#include <vtkCellArray.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkTypeInt64Array.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridReader.h>
#include <vtkXMLUnstructuredGridWriter.h>
#endif

namespace fs = std::filesystem;

namespace pdpm::tools {

namespace {

void requireReadable(const std::string& path) {
    std::error_code ec;
    if (!fs::exists(path, ec)) inputError(path + ": no such file");
    if (fs::is_directory(path, ec)) inputError(path + ": is a directory, expected a file");
    std::ifstream in(path);
    if (!in) inputError(path + ": cannot open for reading");
}

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

std::string extensionOf(const std::string& path) { return lower(fs::path(path).extension().string()); }

} // namespace

bool haveVtk() {
#ifdef PDPM_TOOLS_HAVE_VTK
    return true;
#else
    return false;
#endif
}

// ---- VTU ----------------------------------------------------------------------------------------

#ifdef PDPM_TOOLS_HAVE_VTK
namespace {

vtkDataArray* pointArray(vtkUnstructuredGrid* g, const char* name, int comps, bool required,
                         const std::string& path) {
    vtkDataArray* a = g->GetPointData()->GetArray(name);
    if (!a) {
        if (required) inputError(path + ": point array '" + name + "' missing (not a PowderDPM particle file?)");
        return nullptr;
    }
    if (a->GetNumberOfComponents() != comps)
        inputError(path + ": point array '" + name + "' has " + std::to_string(a->GetNumberOfComponents()) +
                   " components, expected " + std::to_string(comps));
    if (a->GetNumberOfTuples() != g->GetNumberOfPoints())
        inputError(path + ": point array '" + name + "' has the wrong length");
    return a;
}

/// The value of attribute `key` in the text of one XML tag (found = false and "" when absent).
std::string xmlAttribute(const std::string& tag, const std::string& key, bool& found) {
    found = false;
    for (std::size_t at = tag.find(key); at != std::string::npos; at = tag.find(key, at + 1)) {
        if (at == 0 || !std::isspace(static_cast<unsigned char>(tag[at - 1]))) continue;
        std::size_t k = tag.find_first_not_of(" \t\r\n", at + key.size());
        if (k == std::string::npos || tag[k] != '=') continue;
        k = tag.find_first_not_of(" \t\r\n", k + 1);
        if (k == std::string::npos || (tag[k] != '"' && tag[k] != '\'')) continue;
        const std::size_t close = tag.find(tag[k], k + 1);
        if (close == std::string::npos) continue;
        found = true;
        return tag.substr(k + 1, close - k - 1);
    }
    return "";
}

/// Checks the sizes in the XML header of a .vtu before VTK reads the data: VTK trusts them (a
/// negative NumberOfTuples crashes it, a huge NumberOfPoints allocates without bound). Every
/// NumberOfPoints/NumberOfCells/NumberOfTuples/NumberOfComponents must be a non-negative integer
/// (components ≥ 1), point and cell data arrays as long as the piece says, and no array may hold
/// more values than the file can encode: a value takes at least one byte, and zlib compresses at
/// most about 1032:1, so at most kValuesPerByte values per byte of the file.
void checkVtuHeader(const std::string& path) {
    constexpr double kValuesPerByte = 1100;
    std::error_code ec;
    const double fileBytes = double(fs::file_size(path, ec));
    if (ec) return;  // not a regular file: VTK reports what is wrong with it
    const double maxValues = kValuesPerByte * fileBytes;
    std::ifstream in(path, std::ios::binary);
    std::string header, line;
    while (std::getline(in, line)) {  // the text part: up to the raw appended data, if any
        const std::size_t appended = line.find("<AppendedData");
        header += line.substr(0, appended) + "\n";
        if (appended != std::string::npos) break;
    }
    auto count = [&](const std::string& tag, const char* key, double def) {
        bool found = false;
        const std::string v = xmlAttribute(tag, key, found);
        if (!found) return def;
        if (v.empty() || v.size() > 18 || v.find_first_not_of("0123456789") != std::string::npos)
            inputError(path + ": " + key + "=\"" + v + "\" in the XML header is not a count (corrupt file?)");
        const double n = std::stod(v);
        if (n > maxValues)
            inputError(path + ": " + key + "=\"" + v + "\" is impossible for a file of " + fmt(fileBytes) + " bytes (corrupt header?)");
        return n;
    };
    double points = 0, cells = 0;
    std::string section;  // the enclosing PointData, Points, CellData, Cells or FieldData
    for (std::size_t pos = header.find('<'); pos != std::string::npos; pos = header.find('<', pos)) {
        const std::size_t end = header.find('>', pos);
        if (end == std::string::npos) break;  // malformed XML: VTK reports it
        const std::string tag = header.substr(pos + 1, end - pos - 1);
        pos = end + 1;
        const bool closing = !tag.empty() && tag[0] == '/', empty = !tag.empty() && tag.back() == '/';
        const std::size_t start = closing ? 1 : 0;
        const std::string name = tag.substr(start, tag.find_first_of(" \t\r\n/", start) - start);  // npos: to the end
        if (name == "Piece" && !closing) {
            points = count(tag, "NumberOfPoints", 0);
            cells = count(tag, "NumberOfCells", 0);
            if (3 * points > maxValues)
                inputError(path + ": NumberOfPoints=\"" + fmt(points) + "\" is impossible for a file of " + fmt(fileBytes) + " bytes (corrupt header?)");
        } else if (name == "PointData" || name == "Points" || name == "CellData" || name == "Cells" || name == "FieldData") {
            section = closing || empty ? "" : name;
        } else if (name == "DataArray" && !closing) {
            const double comps = count(tag, "NumberOfComponents", 1);
            if (comps < 1) inputError(path + ": NumberOfComponents=\"0\" in the XML header (corrupt file?)");
            const bool pointArray = section == "PointData" || section == "Points", cellArray = section == "CellData";
            const double implied = pointArray ? points : cells;
            const double tuples = count(tag, "NumberOfTuples", pointArray || cellArray ? implied : 0);
            if ((pointArray || cellArray) && tuples != implied)
                inputError(path + ": a " + section + " array has NumberOfTuples=\"" + fmt(tuples) + "\" but the piece has " +
                           (pointArray ? "NumberOfPoints" : "NumberOfCells") + "=\"" + fmt(implied) + "\" (corrupt header?)");
            if (tuples * comps > maxValues)
                inputError(path + ": a DataArray of " + fmt(tuples) + " x " + fmt(comps) + " values is impossible for a file of " +
                           fmt(fileBytes) + " bytes (corrupt header?)");
        }
    }
}

} // namespace
#endif

ParticleSnapshot readVtu(const std::string& path) {
    requireReadable(path);
#ifndef PDPM_TOOLS_HAVE_VTK
    inputError(path + ": this build has no VTK support (configure with -DPDPM_WITH_VTK=ON)");
#else
    vtkObject::GlobalWarningDisplayOff();
    checkVtuHeader(path);
    vtkNew<vtkXMLUnstructuredGridReader> reader;
    if (!reader->CanReadFile(path.c_str())) inputError(path + ": not a VTK XML UnstructuredGrid file");
    reader->SetFileName(path.c_str());
    reader->Update();
    vtkUnstructuredGrid* g = reader->GetOutput();
    if (reader->GetErrorCode() != 0 || !g) inputError(path + ": malformed VTK XML file");
    const vtkIdType n = g->GetNumberOfPoints();

    ParticleSnapshot s;
    vtkFieldData* fd = g->GetFieldData();
    auto field = [&](const char* name, int comps, bool required) -> vtkDataArray* {
        vtkDataArray* a = fd ? fd->GetArray(name) : nullptr;
        if (!a) {
            if (required)
                inputError(path + ": field data '" + name +
                           "' missing (not a PowderDPM particle file? its .vtu files carry time, step and box as field data)");
            return nullptr;
        }
        if (a->GetNumberOfComponents() * a->GetNumberOfTuples() != comps)
            inputError(path + ": field data '" + name + "' must have " + std::to_string(comps) + " values");
        return a;
    };
    auto value = [](vtkDataArray* a, int k) {
        const int c = a->GetNumberOfComponents();
        return a->GetComponent(k / c, k % c);
    };
    s.time = value(field("time", 1, true), 0);
    if (!std::isfinite(s.time)) inputError(path + ": field data 'time' is not a finite number");
    if (vtkDataArray* a = field("step", 1, false)) s.step = std::lround(value(a, 0));
    vtkDataArray* box = field("box", 6, true);
    for (int a = 0; a < 3; ++a) {
        s.boxLo[a] = value(box, 2 * a);
        s.boxHi[a] = value(box, 2 * a + 1);
        if (!(s.boxHi[a] > s.boxLo[a])) inputError(path + ": box has non-positive extent");
    }
    if (vtkDataArray* a = field("periodic", 3, false))
        for (int k = 0; k < 3; ++k) s.periodic[k] = value(a, k) != 0;

    vtkDataArray* id = pointArray(g, "id", 1, false, path);
    vtkDataArray* rad = pointArray(g, "radius", 1, true, path);
    vtkDataArray* mass = pointArray(g, "mass", 1, true, path);
    vtkDataArray* vel = pointArray(g, "velocity", 3, true, path);
    vtkDataArray* om = pointArray(g, "angular_velocity", 3, false, path);
    vtkDataArray* sp = pointArray(g, "species", 1, false, path);
    vtkDataArray* fx = pointArray(g, "fixed", 1, false, path);
    vtkDataArray* co = pointArray(g, "coordination", 1, false, path);
    vtkDataArray* fo = pointArray(g, "force", 3, false, path);

    // Order by id (particle number) when present.
    std::vector<vtkIdType> slot(n);
    for (vtkIdType k = 0; k < n; ++k) slot[k] = k;
    if (id) {
        std::vector<char> seen(n, 0);
        for (vtkIdType k = 0; k < n; ++k) {
            const double d = id->GetComponent(k, 0);
            if (!(d >= 0 && d < double(n)) || seen[vtkIdType(d)])
                inputError(path + ": 'id' must be a permutation of 0…N-1");
            seen[vtkIdType(d)] = 1;
            slot[k] = vtkIdType(d);
        }
    }
    s.x.resize(n); s.v.resize(n); s.r.resize(n); s.m.resize(n);
    if (om) s.omega.resize(n);
    if (sp) s.species.resize(n);
    if (fx) s.fixed.resize(n);
    if (co) s.coordination.resize(n);
    if (fo) s.force.resize(n);
    auto vec = [](vtkDataArray* a, vtkIdType k) {
        return Vec3{a->GetComponent(k, 0), a->GetComponent(k, 1), a->GetComponent(k, 2)};
    };
    for (vtkIdType k = 0; k < n; ++k) {
        const vtkIdType p = slot[k];
        double xyz[3];
        g->GetPoint(k, xyz);
        s.x[p] = {xyz[0], xyz[1], xyz[2]};
        s.v[p] = vec(vel, k);
        s.r[p] = rad->GetComponent(k, 0);
        s.m[p] = mass->GetComponent(k, 0);
        if (!isFinite(s.x[p]) || !isFinite(s.v[p]) || !(s.r[p] > 0) || !std::isfinite(s.r[p]) || !(s.m[p] >= 0))
            inputError(path + ": non-finite particle data, a radius <= 0 or a negative mass at point " + std::to_string(k));
        if (om) s.omega[p] = vec(om, k);
        if (sp) s.species[p] = int(sp->GetComponent(k, 0));
        if (fx) s.fixed[p] = int(fx->GetComponent(k, 0));
        if (co) s.coordination[p] = int(co->GetComponent(k, 0));
        if (fo) s.force[p] = vec(fo, k);
    }
    return s;
#endif
}

void writeVtu(const std::string& path, const ParticleSnapshot& s) {
#ifndef PDPM_TOOLS_HAVE_VTK
    (void)s;
    inputError(path + ": this build has no VTK support");
#else
    const vtkIdType n = vtkIdType(s.size());
    vtkNew<vtkUnstructuredGrid> g;
    vtkNew<vtkPoints> pts;
    pts->SetDataTypeToDouble();
    pts->SetNumberOfPoints(n);
    vtkNew<vtkCellArray> cells;
    for (vtkIdType k = 0; k < n; ++k) {
        pts->SetPoint(k, s.x[k].x, s.x[k].y, s.x[k].z);
        cells->InsertNextCell(1, &k);
    }
    g->SetPoints(pts);
    g->SetCells(1 /*VTK_VERTEX*/, cells);
    auto scalar = [&](const char* name, auto get) {
        vtkNew<vtkDoubleArray> a;
        a->SetName(name);
        a->SetNumberOfValues(n);
        for (vtkIdType k = 0; k < n; ++k) a->SetValue(k, get(k));
        g->GetPointData()->AddArray(a);
    };
    auto integer = [&](const char* name, auto get) {
        vtkNew<vtkIntArray> a;
        a->SetName(name);
        a->SetNumberOfValues(n);
        for (vtkIdType k = 0; k < n; ++k) a->SetValue(k, get(k));
        g->GetPointData()->AddArray(a);
    };
    auto vector = [&](const char* name, auto get) {
        vtkNew<vtkDoubleArray> a;
        a->SetName(name);
        a->SetNumberOfComponents(3);
        a->SetNumberOfTuples(n);
        for (vtkIdType k = 0; k < n; ++k) {
            const Vec3 u = get(k);
            a->SetTuple3(k, u.x, u.y, u.z);
        }
        g->GetPointData()->AddArray(a);
    };
    {
        vtkNew<vtkTypeInt64Array> a;
        a->SetName("id");
        a->SetNumberOfValues(n);
        for (vtkIdType k = 0; k < n; ++k) a->SetValue(k, k);
        g->GetPointData()->AddArray(a);
    }
    scalar("radius", [&](vtkIdType k) { return s.r[k]; });
    scalar("mass", [&](vtkIdType k) { return s.m[k]; });
    vector("velocity", [&](vtkIdType k) { return s.v[k]; });
    vector("angular_velocity", [&](vtkIdType k) { return s.omega.empty() ? Vec3{} : s.omega[k]; });
    integer("species", [&](vtkIdType k) { return s.species.empty() ? 0 : s.species[k]; });
    integer("fixed", [&](vtkIdType k) { return s.fixed.empty() ? 0 : s.fixed[k]; });
    integer("coordination", [&](vtkIdType k) { return s.coordination.empty() ? 0 : s.coordination[k]; });
    vector("force", [&](vtkIdType k) { return s.force.empty() ? Vec3{} : s.force[k]; });
    scalar("force_magnitude", [&](vtkIdType k) { return s.force.empty() ? 0.0 : norm(s.force[k]); });
    auto fieldArray = [&](const char* name, std::vector<double> vals) {
        vtkNew<vtkDoubleArray> a;
        a->SetName(name);
        a->SetNumberOfValues(vtkIdType(vals.size()));
        for (std::size_t k = 0; k < vals.size(); ++k) a->SetValue(vtkIdType(k), vals[k]);
        g->GetFieldData()->AddArray(a);
    };
    fieldArray("time", {s.time});
    fieldArray("step", {double(s.step)});
    fieldArray("box", {s.boxLo.x, s.boxHi.x, s.boxLo.y, s.boxHi.y, s.boxLo.z, s.boxHi.z});
    fieldArray("periodic", {double(s.periodic[0]), double(s.periodic[1]), double(s.periodic[2])});

    vtkNew<vtkXMLUnstructuredGridWriter> w;
    writeVtkXml(path, *w, g);
#endif
}

// ---- PVD ----------------------------------------------------------------------------------------

std::vector<std::string> readPvd(const std::string& path) {
    requireReadable(path);
    std::ifstream in(path);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string text = ss.str();
    static const std::regex header(R"re(<VTKFile\b[^>]*\btype\s*=\s*"Collection")re");
    if (!std::regex_search(text, header)) inputError(path + ": not a VTK collection (.pvd) file (no <VTKFile type=\"Collection\">)");
    // a collection cut short (a run killed while it was written by another program) lists only part of the run
    if (text.find("</Collection>") == std::string::npos || text.find("</VTKFile>") == std::string::npos)
        inputError(path + ": truncated collection (no </Collection> or </VTKFile>)");
    std::vector<std::string> files;
    static const std::regex dataSet(R"re(<DataSet\b[^>]*>)re");
    static const std::regex fileAttr(R"re(\bfile\s*=\s*"([^"]*)")re");
    static const std::regex partAttr(R"re(\bpart\s*=\s*"([^"]*)")re");
    static const std::regex stepAttr(R"re(\btimestep\s*=\s*"([^"]*)")re");
    const fs::path dir = fs::path(path).parent_path();
    for (auto it = std::sregex_iterator(text.begin(), text.end(), dataSet); it != std::sregex_iterator(); ++it) {
        const std::string tag = (*it)[0].str();
        std::smatch m;
        // The kernel lists particles as part 0 and wall geometry as part 1: read particles only.
        if (std::regex_search(tag, m, partAttr) && m[1].str() != "0") continue;
        // The time itself is read from each .vtu's field data; a timestep that is not a finite
        // number still means the collection is damaged.
        if (std::regex_search(tag, m, stepAttr)) {
            const std::string ts = m[1].str();
            double t = 0;
            if (!parseStrictDouble(ts, t)) inputError(path + ": DataSet timestep \"" + ts + "\" is not a finite number");
        }
        if (!std::regex_search(tag, m, fileAttr) || m[1].str().empty()) inputError(path + ": a DataSet without a file attribute: " + tag);
        fs::path f = m[1].str();
        if (f.is_relative()) f = dir / f;
        files.push_back(f.string());
    }
    if (files.empty()) inputError(path + ": collection lists no data sets");
    return files;
}

// ---- FSTAT --------------------------------------------------------------------------------------

std::vector<ContactSnapshot> readFstat(const std::string& path) {
    requireReadable(path);
    std::error_code ec;
    const auto fileBytes = fs::file_size(path, ec);
    std::ifstream in(path);
    std::vector<ContactSnapshot> blocks;
    std::string line;
    long lineNo = 0;
    long expected = -1;  // rows still expected in the current block
    bool haveBoxLine = false;
    auto where = [&] { return path + ":" + std::to_string(lineNo) + ": "; };
    while (std::getline(in, line)) {
        ++lineNo;
        if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
        std::istringstream ls(line);
        if (line[line.find_first_not_of(" \t")] == '#') {
            std::string hash, key;
            ls >> hash >> key;
            if (hash != "#") inputError(where() + "malformed comment line (expected '# time …' or '# box …')");
            if (key == "time") {
                if (expected > 0) inputError(where() + "block ended after too few contact rows");
                ContactSnapshot b;
                std::string kStep, kContacts;
                long m = -1;
                if (!(ls >> b.time >> kStep >> b.step >> kContacts >> m) || kStep != "step" ||
                    kContacts != "contacts" || m < 0)
                    inputError(where() + "malformed header, expected '# time T step S contacts M'");
                if (!ec && double(m) * 34 > double(fileBytes))  // a row is 17 values and their separators
                    inputError(where() + "the header announces " + std::to_string(m) + " contact rows, more than the file can hold");
                b.contacts.reserve(std::size_t(m));
                blocks.push_back(std::move(b));
                expected = m;
                haveBoxLine = false;
            } else if (key == "box") {
                if (blocks.empty() || haveBoxLine) inputError(where() + "'# box' line outside a block header");
                ContactSnapshot& b = blocks.back();
                std::string kPer;
                double v[6];
                int p[3];
                if (!(ls >> v[0] >> v[1] >> v[2] >> v[3] >> v[4] >> v[5] >> kPer >> p[0] >> p[1] >> p[2]) ||
                    kPer != "periodic" || (p[0] != 0 && p[0] != 1) || (p[1] != 0 && p[1] != 1) || (p[2] != 0 && p[2] != 1))
                    inputError(where() + "malformed box line, expected '# box xlo xhi ylo yhi zlo zhi periodic px py pz' (px py pz 0 or 1)");
                for (int a = 0; a < 3; ++a) {
                    b.boxLo[a] = v[2 * a];
                    b.boxHi[a] = v[2 * a + 1];
                    b.periodic[a] = p[a] != 0;
                }
                haveBoxLine = true;
            } else {
                inputError(where() + "unknown comment line '" + key + "'");
            }
            continue;
        }
        if (blocks.empty() || !haveBoxLine) inputError(where() + "contact row before a block header (not an .fstat file?)");
        if (expected <= 0) inputError(where() + "more contact rows than announced in the block header");
        ContactRecord c;
        int sl = 0;
        if (!(ls >> c.i >> c.j >> c.contactPoint.x >> c.contactPoint.y >> c.contactPoint.z >> c.overlap >>
              c.normal.x >> c.normal.y >> c.normal.z >> c.fn >> c.ft.x >> c.ft.y >> c.ft.z >> c.branch.x >>
              c.branch.y >> c.branch.z >> sl))
            inputError(where() + "malformed contact row, expected 17 values 'i j cx cy cz overlap nx ny nz fn ftx fty ftz bx by bz sliding'");
        std::string extra;
        if (ls >> extra) inputError(where() + "too many values in contact row");
        if (c.i < 0) inputError(where() + "negative particle index i");
        if (!isFinite(c.normal) || !isFinite(c.ft) || !isFinite(c.branch) || !std::isfinite(c.fn))
            inputError(where() + "non-finite value");
        // the writer's normal is a unit vector to the last digits; a zero or scaled one would be dropped
        // or weigh the fabric and the layer stresses by its length
        if (!(std::abs(norm(c.normal) - 1) < 1e-6)) inputError(where() + "contact normal of length " + std::to_string(norm(c.normal)) + ", not a unit vector");
        // forces whose products overflow in a stress sum: no granular contact carries them
        if (!(std::abs(c.fn) < 1e100) || !(norm(c.ft) < 1e100) || !(norm(c.branch) < 1e100) || !(std::abs(c.overlap) < 1e100))
            inputError(where() + "force, overlap or branch vector beyond 1e100");
        c.sliding = sl != 0;
        blocks.back().contacts.push_back(c);
        --expected;
    }
    if (expected > 0) inputError(path + ": last block ended after too few contact rows");
    if (blocks.empty()) inputError(path + ": no contact blocks (empty or not an .fstat file)");
    return blocks;
}

void writeFstatBlock(std::ostream& os, const ContactSnapshot& b) {
    os << std::setprecision(17);
    os << "# time " << b.time << " step " << b.step << " contacts " << b.contacts.size() << "\n";
    os << "# box " << b.boxLo.x << ' ' << b.boxHi.x << ' ' << b.boxLo.y << ' ' << b.boxHi.y << ' ' << b.boxLo.z
       << ' ' << b.boxHi.z << " periodic " << b.periodic[0] << ' ' << b.periodic[1] << ' ' << b.periodic[2] << "\n";
    for (const ContactRecord& c : b.contacts) {
        os << c.i << ' ' << c.j << ' ' << c.contactPoint.x << ' ' << c.contactPoint.y << ' ' << c.contactPoint.z << ' '
           << c.overlap << ' ' << c.normal.x << ' ' << c.normal.y << ' ' << c.normal.z << ' ' << c.fn << ' '
           << c.ft.x << ' ' << c.ft.y << ' ' << c.ft.z << ' ' << c.branch.x << ' ' << c.branch.y << ' '
           << c.branch.z << ' ' << (c.sliding ? 1 : 0) << "\n";
    }
}

void writeFstat(const std::string& path, const std::vector<ContactSnapshot>& blocks) {
    writeFileAtomically(path, [&](std::ostream& os) {
        for (const ContactSnapshot& b : blocks) writeFstatBlock(os, b);
    });
}

// ---- frames ---------------------------------------------------------------------------------------

std::vector<Frame> loadFrames(const std::vector<std::string>& paths) {
    if (paths.empty()) inputError("no input files given (--input FILE…)");
    std::vector<ParticleSnapshot> parts;
    std::vector<ContactSnapshot> conts;
    // The same file twice (listed twice, or a .vtu and a .pvd that lists it) would count twice in every
    // average. Files are compared by identity, not by time: replicas or a start file and its
    // preparation may share a time and step.
    std::vector<std::string> seen;
    auto once = [&](const std::string& f) {
        std::error_code ec;
        std::string id = std::filesystem::weakly_canonical(f, ec).string();
        if (ec || id.empty()) id = f;
        if (std::find(seen.begin(), seen.end(), id) != seen.end())
            inputError(f + ": given twice (a file listed twice, or a .vtu and a .pvd that lists it)");
        seen.push_back(id);
    };
    for (const std::string& p : paths) {
        const std::string ext = extensionOf(p);
        if (ext == ".vtu") {
            once(p);
            parts.push_back(readVtu(p));
        } else if (ext == ".pvd") {
            for (const std::string& f : readPvd(p)) {
                once(f);
                parts.push_back(readVtu(f));
            }
        } else if (ext == ".fstat") {
            once(p);
            for (ContactSnapshot& b : readFstat(p)) conts.push_back(std::move(b));
        } else {
            requireReadable(p);
            inputError(p + ": unknown file type '" + ext + "' (expected .vtu, .pvd or .fstat)");
        }
    }
    std::vector<Frame> frames;
    std::vector<char> used(conts.size(), 0);
    for (ParticleSnapshot& s : parts) {
        Frame f;
        f.hasParticles = true;
        // match a contact block: same step if both known, else time within 1e-9 relative
        for (std::size_t k = 0; k < conts.size(); ++k) {
            if (used[k]) continue;
            const bool stepMatch = s.step >= 0 && conts[k].step >= 0 && s.step == conts[k].step;
            const bool timeMatch = (s.step < 0 || conts[k].step < 0) &&
                                   std::abs(s.time - conts[k].time) <= 1e-9 * std::max(1.0, std::abs(s.time));
            if (stepMatch || timeMatch) {
                f.hasContacts = true;
                f.contacts = std::move(conts[k]);
                used[k] = 1;
                break;
            }
        }
        f.particles = std::move(s);
        frames.push_back(std::move(f));
    }
    for (std::size_t k = 0; k < conts.size(); ++k) {
        if (used[k]) continue;
        Frame f;
        f.hasContacts = true;
        f.contacts = std::move(conts[k]);
        frames.push_back(std::move(f));
    }
    std::stable_sort(frames.begin(), frames.end(), [](const Frame& a, const Frame& b) { return a.time() < b.time(); });
    return frames;
}

} // namespace pdpm::tools
