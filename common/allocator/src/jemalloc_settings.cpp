// jemalloc's settings for the programs that stream bricks, read by jemalloc when the program
// starts; MALLOC_CONF in the environment overrides any of them (docs/OPERATIONS.md, "Memory").
//
// A cold start fills soltexd's brick cache and soltex-view's with tens of megabytes of bricks
// that nothing had touched before. In 4 KiB pages that is one page fault per 4 KiB: 14,000 in
// soltexd and 19,000 in soltex-view for the default scene, and under a hypervisor that traps
// each fault they cost as much CPU as evaluating the bricks (docs/PERFORMANCE.md, "Frame
// targets", paragraph 30). glibc's malloc can ask for huge pages only through GLIBC_TUNABLES,
// read before main(), and not for the heaps of its per-thread arenas, which grow a page at a
// time. jemalloc asks for them on every mapping it makes:
// - thp:always: its extents are madvise(MADV_HUGEPAGE)'d, so the kernel fills them 2 MiB at a
//   time even where transparent huge pages are "madvise" only (Debian's default);
// - metadata_thp:auto: its own bookkeeping too, once it grows past a few chunks;
// - narenas:1: one arena for all threads (each thread keeps its cache of small blocks), so
//   that the gRPC threads that make bricks and those that free them fill and reuse the same
//   huge pages instead of one partly used set per arena.
extern "C" {
// The name jemalloc reads; it must have external linkage and C naming.
extern const char* malloc_conf;
const char* malloc_conf = "thp:always,metadata_thp:auto,narenas:1";
}
