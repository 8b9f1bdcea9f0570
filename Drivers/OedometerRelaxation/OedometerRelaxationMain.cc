// OedometerRelaxation driver program; the simulation is in OedometerRelaxation.h.
#include "OedometerRelaxation.h"

int main(int argc, char** argv) { return pdpm::OedometerRelaxation().run(argc, argv); }
