#include "OutputFiles.h"

#include "Core/Error.h"

#include <cstdio>
#include <filesystem>
#include <fstream>

#ifdef PDPM_TOOLS_HAVE_VTK
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkXMLImageDataWriter.h>
#endif

namespace fs = std::filesystem;

namespace pdpm::tools {

void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& fill) {
    const std::string tmp = path + ".tmp";
    {
        std::ofstream os(tmp);
        if (!os) inputError(path + ": cannot open for writing");
        fill(os);
        os.flush();
        if (!os) inputError(path + ": write failed");
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) inputError(path + ": cannot rename from " + tmp + ": " + ec.message());
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
    const std::string tmp = path + ".tmp";
    vtkNew<vtkXMLImageDataWriter> w;
    w->SetFileName(tmp.c_str());
    w->SetInputData(img);
    w->SetDataModeToAppended();
    if (w->Write() != 1) inputError(path + ": cannot write");
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) inputError(path + ": cannot rename from " + tmp + ": " + ec.message());
#endif
}

} // namespace pdpm::tools
