define dso_local void @trax_main() {
entry:
  %s = alloca %"generics::Square", align 8
  br label %start

start:                                            ; preds = %entry
  %0 = call float @"trax::rand"()
  %1 = insertvalue %"generics::Square" undef, float %0, 0
  store %"generics::Square" %1, %"generics::Square"* %s, align 4
  %2 = call float @"generics::Shape::twice::<Square>"(%"generics::Square"* %s)
  %3 = call float @"generics::biggest::<f32>"(float %2, float 1.000000e+00)
  call void @"trax::store_f32"(i32 0, float %3)
  %4 = call i32 @"trax::global_id"()
  %5 = call i32 @"generics::biggest::<u32>"(i32 %4, i32 3)
  call void @"trax::store_u32"(i32 4, i32 %5)
  ret void
}

define internal float @"generics::Shape::twice::<Square>"(%"generics::Square"* %0) {
entry:
  %self = alloca %"generics::Square"*, align 4
  store %"generics::Square"* %0, %"generics::Square"** %self, align 4
  br label %start

start:                                            ; preds = %entry
  %1 = load %"generics::Square"*, %"generics::Square"** %self, align 4
  %2 = call float @"generics::<Square as Shape>::area"(%"generics::Square"* %1)
  %3 = fmul float 2.000000e+00, %2
  ret float %3
}

define internal float @"generics::biggest::<f32>"(float %0, float %1) {
entry:
  %a = alloca float, align 4
  store float %0, float* %a, align 4
  %b = alloca float, align 4
  store float %1, float* %b, align 4
  %if.value = alloca float, align 4
  br label %start

start:                                            ; preds = %entry
  %2 = load float, float* %a, align 4
  %3 = load float, float* %b, align 4
  %4 = fcmp ogt float %2, %3
  br i1 %4, label %cond.true, label %if.else

if.else:                                          ; preds = %start
  %5 = load float, float* %b, align 4
  store float %5, float* %if.value, align 4
  br label %if.end

if.end:                                           ; preds = %if.else, %cond.true
  %6 = load float, float* %if.value, align 4
  ret float %6

cond.true:                                        ; preds = %start
  %7 = load float, float* %a, align 4
  store float %7, float* %if.value, align 4
  br label %if.end
}

define internal i32 @"generics::biggest::<u32>"(i32 %0, i32 %1) {
entry:
  %a = alloca i32, align 4
  store i32 %0, i32* %a, align 4
  %b = alloca i32, align 4
  store i32 %1, i32* %b, align 4
  %if.value = alloca i32, align 4
  br label %start

start:                                            ; preds = %entry
  %2 = load i32, i32* %a, align 4
  %3 = load i32, i32* %b, align 4
  %4 = icmp ugt i32 %2, %3
  br i1 %4, label %cond.true, label %if.else

if.else:                                          ; preds = %start
  %5 = load i32, i32* %b, align 4
  store i32 %5, i32* %if.value, align 4
  br label %if.end

if.end:                                           ; preds = %if.else, %cond.true
  %6 = load i32, i32* %if.value, align 4
  ret i32 %6

cond.true:                                        ; preds = %start
  %7 = load i32, i32* %a, align 4
  store i32 %7, i32* %if.value, align 4
  br label %if.end
}

define internal float @"generics::<Square as Shape>::area"(%"generics::Square"* %0) {
entry:
  %self = alloca %"generics::Square"*, align 4
  store %"generics::Square"* %0, %"generics::Square"** %self, align 4
  br label %start

start:                                            ; preds = %entry
  %1 = load %"generics::Square"*, %"generics::Square"** %self, align 4
  %2 = getelementptr inbounds %"generics::Square", %"generics::Square"* %1, i32 0, i32 0
  %3 = load float, float* %2, align 4
  %4 = load %"generics::Square"*, %"generics::Square"** %self, align 4
  %5 = getelementptr inbounds %"generics::Square", %"generics::Square"* %4, i32 0, i32 0
  %6 = load float, float* %5, align 4
  %7 = fmul float %3, %6
  ret float %7
}

