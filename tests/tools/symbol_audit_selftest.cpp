// The symbol audit's negative control (tests/firmware/proofs/firmware_symbol_audit.sh): an object that references malloc,
// free and operator new/delete. The audit must reject it; if it does not, a clean audit proves nothing.
#include <cstddef>
#include <cstdlib>
#include <new>

void* symbol_audit_selftest_malloc(std::size_t n) { return std::malloc(n); }
void symbol_audit_selftest_free(void* p) { std::free(p); }
int* symbol_audit_selftest_new() { return new int(1); }
void symbol_audit_selftest_delete(int* p) { delete p; }
