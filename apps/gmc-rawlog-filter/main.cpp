#include "gmc/apps/rawlog_filter_app.h"

int main(int argc, char** argv) {
  return gmc::apps::runApp<gmc::apps::RawlogFilterApp>("gmc-rawlog-filter", argc, argv);
}
