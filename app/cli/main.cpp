// kcwarp-cli: the headless face of kcwarp (ARCHITECTURE.md, "Command line"); the commands are kc_cli's.

#include "cli_main.h"

int main(int argc, char** argv) { return kc::cli::runCli(argc, argv); }
