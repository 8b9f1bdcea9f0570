// Output helpers shared by the tools: atomic text files (written to NAME.tmp, renamed when
// complete), CSV tables with a documented header, and VTK image data (.vti) for ParaView.
#pragma once
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

class vtkXMLWriter;
class vtkDataObject;

namespace pdpm::tools {

/// Writes a file through `fill`, first to PATH.tmp, then renames it to PATH. InputError when the
/// directory is not writable or the rename fails; PATH.tmp is removed on every failure (also when
/// `fill` throws).
void writeFileAtomically(const std::string& path, const std::function<void(std::ostream&)>& fill);

/// The same for writers that take a file name (VTK): `write(tmp)` writes PATH.tmp and returns false
/// on failure. InputError when PATH.tmp cannot be opened, written or renamed; PATH.tmp is removed.
void writeThroughTmp(const std::string& path, const std::function<bool(const std::string& tmp)>& write);

/// A VTK XML writer (appended data) writing `data` to PATH through writeThroughTmp, VTK's own warnings
/// silenced (the failure is reported in one line). Only in builds with VTK.
void writeVtkXml(const std::string& path, vtkXMLWriter& writer, vtkDataObject* data);

/// Creates a directory (and parents); InputError on failure.
void ensureDirectory(const std::string& dir);

/// "dir/name" (no double slashes).
std::string joinPath(const std::string& dir, const std::string& name);

/// Formats a double with 10 significant digits (enough for post-processed fields).
std::string fmt(double x);

/// A named scalar or vector field on a regular image grid, values in x-fastest order.
struct ImageField {
    std::string name;
    int components = 1;
    std::vector<double> values;  ///< size = components * nx * ny * nz
};

/// Writes VTK XML ImageData (.vti, binary appended), readable by ParaView; atomic.
/// `origin` is the centre of the first cell, `spacing` the cell size. Throws InputError when the
/// library was built without VTK.
void writeVti(const std::string& path, const int dims[3], const double origin[3],
              const double spacing[3], const std::vector<ImageField>& fields, double time);

} // namespace pdpm::tools
