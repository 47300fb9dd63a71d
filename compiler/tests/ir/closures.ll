define dso_local void @trax_main() {
entry:
  %k = alloca float, align 4
  %n = alloca i32, align 4
  %bump = alloca { i32* }, align 8
  br label %start

start:                                            ; preds = %entry
  %0 = call float @"trax::rand"()
  store float %0, float* %k, align 4
  store i32 0, i32* %n, align 4
  %1 = insertvalue { i32* } undef, i32* %n, 0
  store { i32* } %1, { i32* }* %bump, align 4
  call void @"trax_main::{closure@8:20}"({ i32* }* %bump, i32 2)
  %2 = insertvalue { float* } undef, float* %k, 0
  %3 = call float @"closures::apply::<closure(f32) -> f32>"({ float* } %2, float 2.000000e+00)
  call void @"trax::store_f32"(i32 0, float %3)
  %4 = load i32, i32* %n, align 4
  call void @"trax::store_u32"(i32 4, i32 %4)
  ret void
}

define internal float @"closures::apply::<closure(f32) -> f32>"({ float* } %0, float %1) {
entry:
  %f = alloca { float* }, align 8
  store { float* } %0, { float* }* %f, align 4
  %x = alloca float, align 4
  store float %1, float* %x, align 4
  br label %start

start:                                            ; preds = %entry
  %2 = load float, float* %x, align 4
  %3 = call float @"trax_main::{closure@10:30}"({ float* }* %f, float %2)
  ret float %3
}

