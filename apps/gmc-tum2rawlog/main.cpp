#include "gmc/apps/tum2rawlog_app.h"

int main(int argc, char** argv) {
  return gmc::apps::runApp<gmc::apps::Tum2RawlogApp>("gmc-tum2rawlog", argc, argv);
}
