define dso_local void @trax_main() {
entry:
  %tmp = alloca { float, i32 }, align 8
  %x = alloca float, align 4
  %y = alloca i32, align 4
  br label %start

start:                                            ; preds = %entry
  %0 = call i32 @"trax::global_id"()
  %1 = insertvalue { i32, float } undef, i32 %0, 0
  %2 = insertvalue { i32, float } %1, float 1.500000e+00, 1
  %3 = call { float, i32 } @"tuples::split"({ i32, float } %2)
  store { float, i32 } %3, { float, i32 }* %tmp, align 4
  %4 = getelementptr inbounds { float, i32 }, { float, i32 }* %tmp, i32 0, i32 0
  %5 = load float, float* %4, align 4
  store float %5, float* %x, align 4
  %6 = getelementptr inbounds { float, i32 }, { float, i32 }* %tmp, i32 0, i32 1
  %7 = load i32, i32* %6, align 4
  store i32 %7, i32* %y, align 4
  %8 = load float, float* %x, align 4
  %9 = load i32, i32* %y, align 4
  %10 = uitofp i32 %9 to float
  %11 = fadd float %8, %10
  call void @"trax::store_f32"(i32 0, float %11)
  ret void

let.else:                                         ; No predecessors!
  unreachable
}

define internal { float, i32 } @"tuples::split"({ i32, float } %0) {
entry:
  %p = alloca { i32, float }, align 8
  store { i32, float } %0, { i32, float }* %p, align 4
  %a = alloca i32, align 4
  %b = alloca float, align 4
  br label %start

start:                                            ; preds = %entry
  %1 = getelementptr inbounds { i32, float }, { i32, float }* %p, i32 0, i32 0
  %2 = load i32, i32* %1, align 4
  store i32 %2, i32* %a, align 4
  %3 = getelementptr inbounds { i32, float }, { i32, float }* %p, i32 0, i32 1
  %4 = load float, float* %3, align 4
  store float %4, float* %b, align 4
  %5 = load float, float* %b, align 4
  %6 = insertvalue { float, i32 } undef, float %5, 0
  %7 = load i32, i32* %a, align 4
  %8 = insertvalue { float, i32 } %6, i32 %7, 1
  ret { float, i32 } %8

let.else:                                         ; No predecessors!
  unreachable
}

