#include "UniaxialCyclic.h"

#ifdef PDPM_DRIVER_VTK
#include "IO/VtkWriter.h"
#endif

int main(int argc, char** argv) { return UniaxialCyclic().run(argc, argv); }
