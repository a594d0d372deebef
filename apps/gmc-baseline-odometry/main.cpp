#include "gmc/apps/baseline_app.h"

int main(int argc, char** argv) {
  return gmc::apps::runApp<gmc::apps::BaselineApp>("gmc-baseline-odometry", argc, argv);
}
