; 64-bit division and int/float conversions for MIPS32 (TRaX has no compiler-rt).
; Only operations the MIPS32r6 backend lowers inline are used here.

define internal { i64, i64 } @__trax_udivmod64(i64 %n, i64 %d) #0 {
entry:
  br label %loop
loop:
  %i = phi i32 [ 0, %entry ], [ %i1, %loop ]
  %q = phi i64 [ 0, %entry ], [ %q1, %loop ]
  %r = phi i64 [ 0, %entry ], [ %r2, %loop ]
  %sh = sub i32 63, %i
  %sh64 = zext i32 %sh to i64
  %bit = lshr i64 %n, %sh64
  %b1 = and i64 %bit, 1
  %top = lshr i64 %r, 63
  %over = icmp ne i64 %top, 0
  %rs = shl i64 %r, 1
  %r1 = or i64 %rs, %b1
  %ge0 = icmp uge i64 %r1, %d
  %ge = or i1 %ge0, %over
  %rsub = sub i64 %r1, %d
  %r2 = select i1 %ge, i64 %rsub, i64 %r1
  %qs = shl i64 %q, 1
  %qb = zext i1 %ge to i64
  %q1 = or i64 %qs, %qb
  %i1 = add i32 %i, 1
  %done = icmp eq i32 %i1, 64
  br i1 %done, label %exit, label %loop
exit:
  %a = insertvalue { i64, i64 } undef, i64 %q1, 0
  %b = insertvalue { i64, i64 } %a, i64 %r2, 1
  ret { i64, i64 } %b
}

define i64 @__udivdi3(i64 %n, i64 %d) #0 {
  %qr = call { i64, i64 } @__trax_udivmod64(i64 %n, i64 %d)
  %q = extractvalue { i64, i64 } %qr, 0
  ret i64 %q
}

define i64 @__umoddi3(i64 %n, i64 %d) #0 {
  %qr = call { i64, i64 } @__trax_udivmod64(i64 %n, i64 %d)
  %r = extractvalue { i64, i64 } %qr, 1
  ret i64 %r
}

define i64 @__divdi3(i64 %a, i64 %b) #0 {
  %na = icmp slt i64 %a, 0
  %nb = icmp slt i64 %b, 0
  %ma = sub i64 0, %a
  %mb = sub i64 0, %b
  %ua = select i1 %na, i64 %ma, i64 %a
  %ub = select i1 %nb, i64 %mb, i64 %b
  %qr = call { i64, i64 } @__trax_udivmod64(i64 %ua, i64 %ub)
  %q = extractvalue { i64, i64 } %qr, 0
  %neg = xor i1 %na, %nb
  %mq = sub i64 0, %q
  %r = select i1 %neg, i64 %mq, i64 %q
  ret i64 %r
}

define i64 @__moddi3(i64 %a, i64 %b) #0 {
  %na = icmp slt i64 %a, 0
  %nb = icmp slt i64 %b, 0
  %ma = sub i64 0, %a
  %mb = sub i64 0, %b
  %ua = select i1 %na, i64 %ma, i64 %a
  %ub = select i1 %nb, i64 %mb, i64 %b
  %qr = call { i64, i64 } @__trax_udivmod64(i64 %ua, i64 %ub)
  %m = extractvalue { i64, i64 } %qr, 1
  %mm = sub i64 0, %m
  %r = select i1 %na, i64 %mm, i64 %m
  ret i64 %r
}

define double @__floatundidf(i64 %a) #0 {
  %h64 = lshr i64 %a, 32
  %h = trunc i64 %h64 to i32
  %l = trunc i64 %a to i32
  %hf = uitofp i32 %h to double
  %lf = uitofp i32 %l to double
  %hs = fmul double %hf, 4294967296.0
  %r = fadd double %hs, %lf
  ret double %r
}

define double @__floatdidf(i64 %a) #0 {
  %h64 = ashr i64 %a, 32
  %h = trunc i64 %h64 to i32
  %l = trunc i64 %a to i32
  %hf = sitofp i32 %h to double
  %lf = uitofp i32 %l to double
  %hs = fmul double %hf, 4294967296.0
  %r = fadd double %hs, %lf
  ret double %r
}

define float @__floatundisf(i64 %a) #0 {
  %d = call double @__floatundidf(i64 %a)
  %r = fptrunc double %d to float
  ret float %r
}

define float @__floatdisf(i64 %a) #0 {
  %d = call double @__floatdidf(i64 %a)
  %r = fptrunc double %d to float
  ret float %r
}

define i64 @__fixunsdfdi(double %x) #0 {
  %hf = fmul double %x, 0x3DF0000000000000
  %h = fptoui double %hf to i32
  %hb = uitofp i32 %h to double
  %hs = fmul double %hb, 4294967296.0
  %lf = fsub double %x, %hs
  %l = fptoui double %lf to i32
  %h64 = zext i32 %h to i64
  %hsh = shl i64 %h64, 32
  %l64 = zext i32 %l to i64
  %r = or i64 %hsh, %l64
  ret i64 %r
}

define i64 @__fixdfdi(double %x) #0 {
  %neg = fcmp olt double %x, 0.0
  %a = call double @llvm.fabs.f64(double %x)
  %u = call i64 @__fixunsdfdi(double %a)
  %m = sub i64 0, %u
  %r = select i1 %neg, i64 %m, i64 %u
  ret i64 %r
}

define i64 @__fixunssfdi(float %x) #0 {
  %d = fpext float %x to double
  %r = call i64 @__fixunsdfdi(double %d)
  ret i64 %r
}

define i64 @__fixsfdi(float %x) #0 {
  %d = fpext float %x to double
  %r = call i64 @__fixdfdi(double %d)
  ret i64 %r
}

declare double @llvm.fabs.f64(double)

attributes #0 = { nounwind "no-builtins" }
