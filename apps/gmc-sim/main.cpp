#include "gmc/apps/sim_app.h"

int main(int argc, char** argv) {
  return gmc::apps::runApp<gmc::apps::SimApp>("gmc-sim", argc, argv);
}
