#include <CppUTest/CommandLineTestRunner.h>
#include <CppUTest/MemoryLeakWarningPlugin.h>

// Several suites run real threads (the dashboard's I/O thread, the study's workers, the monitor's receive thread)
// that allocate while the test thread does. CppUTest's leak detector keeps one table of every allocation and is not
// thread-safe by default: concurrent new/delete corrupted it under load (a spurious "allocation/deallocation type
// mismatch" in the dashboard suite in CI, whose failure then skipped the test's server.stop()). The mutex-guarded
// overloads keep the leak check and make it sound with threads.
int main(int argc, char** argv) {
  MemoryLeakWarningPlugin::turnOnThreadSafeNewDeleteOverloads();
  return CommandLineTestRunner::RunAllTests(argc, argv);
}
