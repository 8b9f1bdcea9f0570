#include "DeviatoricD2.h"

#ifdef PDPM_DRIVER_VTK
#include "IO/VtkWriter.h"
#endif

int main(int argc, char** argv) { return DeviatoricD2().run(argc, argv); }
