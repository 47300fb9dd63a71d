; Linker test: a second LLVM object with the MIPS32r6 PC-relative relocations
; (R_MIPS_PCHI16/PCLO16, PC19_S2, PC21_S2, PC16, PC26_S2) and %hi/%lo pairs whose addend
; carries into the high half, from module assembly; an MSA
; function and a function called by link_kernel.ll.
target datalayout = "e-m:m-p:32:32-i8:8:32-i16:16:32-i64:64-n32-S64"
target triple = "mipsel-unknown-none"

module asm ".text"
module asm ".globl pcrel_probe"
module asm ".type pcrel_probe,@function"
module asm ".set noreorder"
module asm "pcrel_probe:"
module asm "  auipc $2, %pcrel_hi(pc_data)"
module asm "  addiu $2, $2, %pcrel_lo(pc_data+4)"
module asm "  lwpc $3, pc_data"
module asm "  beqzc $4, lib_step"
module asm "  beq $4, $5, lib_step"
module asm "  nop"
module asm "  bc lib_step"
module asm "  jrc $ra"
module asm ".globl hi_lo_probe"
module asm "hi_lo_probe:"
module asm "  lui $2, %hi(pc_data+0x7ffc)"
module asm "  lui $3, %hi(pc_data+0x7ffc)"
module asm "  addiu $2, $2, %lo(pc_data+0x7ffc)"
module asm "  lw $3, %lo(pc_data+0x7ffc)($3)"
module asm "  jrc $ra"
module asm ".set reorder"

@pc_data = global [4 x i32] [i32 1, i32 2, i32 3, i32 4], align 4
@counter = internal global i32 0, align 4
@lib_zeroes = global [64 x i32] zeroinitializer, align 4

declare i32 @pick(i32)

define i32 @lib_step(i32 %x) {
  %c = load i32, i32* @counter, align 4
  %n = add i32 %c, %x
  store i32 %n, i32* @counter, align 4
  %z = getelementptr [64 x i32], [64 x i32]* @lib_zeroes, i32 0, i32 %x
  %zv = load i32, i32* %z, align 4
  %r = add i32 %n, %zv
  ret i32 %r
}

define float @lib_dot(<4 x float> %v) {
  %m = fmul <4 x float> %v, <float 0.5, float 0.25, float 2.0, float 1.0>
  %a = extractelement <4 x float> %m, i32 0
  %b = extractelement <4 x float> %m, i32 1
  %c = extractelement <4 x float> %m, i32 2
  %d = extractelement <4 x float> %m, i32 3
  %ab = fadd float %a, %b
  %cd = fadd float %c, %d
  %s = fadd float %ab, %cd
  ret float %s
}
