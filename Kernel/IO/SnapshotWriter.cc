#include "IO/SnapshotWriter.h"

namespace pdpm {

SnapshotWriterFactory& snapshotWriterFactory() {
    static SnapshotWriterFactory f;
    return f;
}

} // namespace pdpm
