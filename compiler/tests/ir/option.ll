define dso_local void @trax_main() {
entry:
  %tmp = alloca %"trax::lang::Option<Hit>", align 8
  %h = alloca %"option::Hit", align 8
  br label %start

start:                                            ; preds = %entry
  %0 = call float @"trax::rand"()
  %1 = call %"trax::lang::Option<Hit>" @"option::intersect"(float %0)
  store %"trax::lang::Option<Hit>" %1, %"trax::lang::Option<Hit>"* %tmp, align 4
  %tag = getelementptr inbounds %"trax::lang::Option<Hit>", %"trax::lang::Option<Hit>"* %tmp, i32 0, i32 0
  %tag1 = load i32, i32* %tag, align 4
  %2 = icmp eq i32 %tag1, 1
  br i1 %2, label %pat.ok, label %if.else

if.else:                                          ; preds = %start
  br label %if.end

if.end:                                           ; preds = %if.else, %pat.ok
  ret void

pat.ok:                                           ; preds = %start
  %payload = getelementptr inbounds %"trax::lang::Option<Hit>", %"trax::lang::Option<Hit>"* %tmp, i32 0, i32 1
  %3 = getelementptr inbounds %"Option<Hit>::Some", %"Option<Hit>::Some"* %payload, i32 0, i32 0
  %4 = load %"option::Hit", %"option::Hit"* %3, align 4
  store %"option::Hit" %4, %"option::Hit"* %h, align 4
  %5 = getelementptr inbounds %"option::Hit", %"option::Hit"* %h, i32 0, i32 1
  %6 = load i32, i32* %5, align 4
  call void @"trax::store_u32"(i32 0, i32 %6)
  br label %if.end
}

define internal %"trax::lang::Option<Hit>" @"option::intersect"(float %0) {
entry:
  %t = alloca float, align 4
  store float %0, float* %t, align 4
  %if.value = alloca %"trax::lang::Option<Hit>", align 8
  br label %start

start:                                            ; preds = %entry
  %1 = load float, float* %t, align 4
  %2 = fcmp ogt float %1, 0.000000e+00
  br i1 %2, label %cond.true, label %if.else

if.else:                                          ; preds = %start
  store %"trax::lang::Option<Hit>" zeroinitializer, %"trax::lang::Option<Hit>"* %if.value, align 4
  br label %if.end

if.end:                                           ; preds = %if.else, %cond.true
  %3 = load %"trax::lang::Option<Hit>", %"trax::lang::Option<Hit>"* %if.value, align 4
  ret %"trax::lang::Option<Hit>" %3

cond.true:                                        ; preds = %start
  %4 = load float, float* %t, align 4
  %5 = insertvalue %"option::Hit" undef, float %4, 0
  %6 = insertvalue %"option::Hit" %5, i32 7, 1
  %7 = insertvalue %"Option<Hit>::Some" undef, %"option::Hit" %6, 0
  %8 = insertvalue %"trax::lang::Option<Hit>" { i32 1, %"Option<Hit>::Some" undef }, %"Option<Hit>::Some" %7, 1
  store %"trax::lang::Option<Hit>" %8, %"trax::lang::Option<Hit>"* %if.value, align 4
  br label %if.end
}

