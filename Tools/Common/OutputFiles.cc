#include "OutputFiles.h"

#include "Core/Error.h"
#include "IO/AtomicFile.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#ifdef PDPM_TOOLS_HAVE_VTK
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkObject.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataWriter.h>
#include <vtkXMLWriter.h>
#endif

namespace fs = std::filesystem;

namespace pdpm::tools {

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& fill) {
    AtomicOFStream os(path);  // writes PATH.tmp; removes it again unless commit() succeeds
    fill(os);
    os.commit();
}

void writeThroughTmp(const std::string& path, const std::function<bool(const std::string& tmp)>& write) {
    const std::string tmp = path + ".tmp";
    struct RemoveTmp {  // on every way out but the successful rename
        const std::string& p;
        bool keep = false;
        ~RemoveTmp() {
            std::error_code ec;
            if (!keep) fs::remove(p, ec);
        }
    };
    {
        errno = 0;
        std::ofstream probe(tmp);  // the writer's own failure to open is not always reported
        if (!probe) inputError("cannot open '" + tmp + "' for writing" + (errno ? ": " + std::string(std::strerror(errno)) : ""));
    }
    RemoveTmp guard{tmp};
    if (!write(tmp)) inputError(path + ": cannot write");
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) inputError("cannot rename '" + tmp + "' to '" + path + "': " + ec.message());
    guard.keep = true;
}

void ensureDirectory(const std::string& dir) {
    if (dir.empty()) return;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir)) inputError("--output " + dir + ": cannot create directory");
}

std::string joinPath(const std::string& dir, const std::string& name) {
    if (dir.empty() || dir == ".") return name;
    return (fs::path(dir) / name).string();
}

std::string fmt(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.10g", x);
    return buf;
}

void writeVti(const std::string& path, const int dims[3], const double origin[3], const double spacing[3],
              const std::vector<ImageField>& fields, double time) {
#ifndef PDPM_TOOLS_HAVE_VTK
    (void)dims; (void)origin; (void)spacing; (void)fields; (void)time;
    inputError(path + ": this build has no VTK support (use CSV output)");
#else
    vtkNew<vtkImageData> img;
    img->SetDimensions(dims[0], dims[1], dims[2]);
    img->SetOrigin(origin[0], origin[1], origin[2]);
    img->SetSpacing(spacing[0], spacing[1], spacing[2]);
    const vtkIdType n = vtkIdType(dims[0]) * dims[1] * dims[2];
    for (const ImageField& f : fields) {
        vtkNew<vtkDoubleArray> a;
        a->SetName(f.name.c_str());
        a->SetNumberOfComponents(f.components);
        a->SetNumberOfTuples(n);
        for (vtkIdType k = 0; k < n * f.components; ++k) a->SetValue(k, f.values[std::size_t(k)]);
        img->GetPointData()->AddArray(a);
    }
    vtkNew<vtkDoubleArray> t;
    t->SetName("TimeValue");
    t->InsertNextValue(time);
    img->GetFieldData()->AddArray(t);
    vtkNew<vtkXMLImageDataWriter> w;
    writeVtkXml(path, *w, img);
#endif
}

#ifdef PDPM_TOOLS_HAVE_VTK
void writeVtkXml(const std::string& path, vtkXMLWriter& writer, vtkDataObject* data) {
    vtkObject::GlobalWarningDisplayOff();  // failures are reported in one line by writeThroughTmp
    writeThroughTmp(path, [&](const std::string& tmp) {
        writer.SetFileName(tmp.c_str());
        writer.SetInputData(data);
        writer.SetDataModeToAppended();
        return writer.Write() == 1 && writer.GetErrorCode() == 0;
    });
}
#endif

} // namespace pdpm::tools
