; Linker test: an LLVM object like the TRaX compiler's (MSA vectors, a jump table,
; a constructor in .init_array, debug line info), calling into link_lib.ll.
target datalayout = "e-m:m-p:32:32-i8:8:32-i16:16:32-i64:64-n32-S64"
target triple = "mipsel-unknown-none"

@vec = global <4 x float> <float 1.0, float 2.0, float 3.0, float 4.0>, align 16
@result = global i32 0, align 4
@started = internal global i32 0, align 4
@__trax_scene_framebuffer = external global [2 x i32]
@llvm.global_ctors = appending global [1 x { i32, void ()*, i8* }] [{ i32, void ()*, i8* } { i32 65535, void ()* @kernel_init, i8* null }]

declare i32 @lib_step(i32)
declare i32 @pcrel_probe()
declare float @lib_dot(<4 x float>)

define internal void @kernel_init() !dbg !10 {
  store i32 7, i32* @started, align 4, !dbg !13
  ret void, !dbg !14
}

define i32 @pick(i32 %x) !dbg !15 {
entry:
  switch i32 %x, label %def [
    i32 0, label %a
    i32 1, label %b
    i32 2, label %c
    i32 3, label %d
    i32 4, label %e
    i32 5, label %f
  ], !dbg !16
a:
  %ra = call i32 @lib_step(i32 1), !dbg !17
  ret i32 %ra, !dbg !17
b:
  ret i32 11, !dbg !18
c:
  %s = load i32, i32* @started, align 4, !dbg !19
  ret i32 %s, !dbg !19
d:
  ret i32 47, !dbg !20
e:
  %p = call i32 @pcrel_probe(), !dbg !21
  ret i32 %p, !dbg !21
f:
  ret i32 5, !dbg !22
def:
  %m = mul i32 %x, 9, !dbg !23
  ret i32 %m, !dbg !23
}

define void @trax_main() !dbg !24 {
entry:
  %v = load <4 x float>, <4 x float>* @vec, align 16, !dbg !25
  %w = fmul <4 x float> %v, %v, !dbg !25
  store <4 x float> %w, <4 x float>* @vec, align 16, !dbg !26
  %d = call float @lib_dot(<4 x float> %w), !dbg !27
  %di = fptosi float %d to i32, !dbg !27
  %k = call i32 @pick(i32 %di), !dbg !28
  %fbp = getelementptr [2 x i32], [2 x i32]* @__trax_scene_framebuffer, i32 0, i32 0, !dbg !29
  %fb = load i32, i32* %fbp, align 4, !dbg !29
  %sum = add i32 %k, %fb, !dbg !29
  store i32 %sum, i32* @result, align 4, !dbg !30
  ret void, !dbg !31
}

!llvm.dbg.cu = !{!0}
!llvm.module.flags = !{!3, !4}

!0 = distinct !DICompileUnit(language: DW_LANG_C99, file: !1, producer: "trax linker test", isOptimized: true, runtimeVersion: 0, emissionKind: LineTablesOnly)
!1 = !DIFile(filename: "link_kernel.rs", directory: "/trax/tests")
!3 = !{i32 2, !"Debug Info Version", i32 3}
!4 = !{i32 7, !"Dwarf Version", i32 4}
!5 = !DISubroutineType(types: !{})
!10 = distinct !DISubprogram(name: "kernel_init", scope: !1, file: !1, line: 3, type: !5, scopeLine: 3, spFlags: DISPFlagDefinition | DISPFlagOptimized, unit: !0)
!13 = !DILocation(line: 4, column: 5, scope: !10)
!14 = !DILocation(line: 5, column: 1, scope: !10)
!15 = distinct !DISubprogram(name: "pick", scope: !1, file: !1, line: 8, type: !5, scopeLine: 8, spFlags: DISPFlagDefinition | DISPFlagOptimized, unit: !0)
!16 = !DILocation(line: 9, column: 5, scope: !15)
!17 = !DILocation(line: 10, column: 14, scope: !15)
!18 = !DILocation(line: 11, column: 14, scope: !15)
!19 = !DILocation(line: 12, column: 14, scope: !15)
!20 = !DILocation(line: 13, column: 14, scope: !15)
!21 = !DILocation(line: 14, column: 14, scope: !15)
!22 = !DILocation(line: 15, column: 14, scope: !15)
!23 = !DILocation(line: 16, column: 14, scope: !15)
!24 = distinct !DISubprogram(name: "trax_main", scope: !1, file: !1, line: 20, type: !5, scopeLine: 20, spFlags: DISPFlagDefinition | DISPFlagOptimized, unit: !0)
!25 = !DILocation(line: 21, column: 9, scope: !24)
!26 = !DILocation(line: 22, column: 5, scope: !24)
!27 = !DILocation(line: 23, column: 13, scope: !24)
!28 = !DILocation(line: 24, column: 13, scope: !24)
!29 = !DILocation(line: 25, column: 15, scope: !24)
!30 = !DILocation(line: 26, column: 5, scope: !24)
!31 = !DILocation(line: 27, column: 1, scope: !24)
