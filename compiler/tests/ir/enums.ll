define dso_local void @trax_main() {
entry:
  %if.value = alloca %"enums::Material", align 8
  %variant = alloca %"enums::Material", align 8
  %variant2 = alloca %"enums::Material", align 8
  %m = alloca %"enums::Material", align 8
  br label %start

start:                                            ; preds = %entry
  %0 = call i32 @"trax::global_id"()
  %1 = icmp eq i32 %0, 0
  br i1 %1, label %cond.true, label %if.else

if.else:                                          ; preds = %start
  %2 = getelementptr inbounds %"enums::Material", %"enums::Material"* %variant2, i32 0, i32 1
  store [1 x i32] zeroinitializer, [1 x i32]* %2, align 4
  %tag3 = getelementptr inbounds %"enums::Material", %"enums::Material"* %variant2, i32 0, i32 0
  store i32 2, i32* %tag3, align 4
  %payload4 = getelementptr inbounds %"enums::Material", %"enums::Material"* %variant2, i32 0, i32 1
  %variant5 = bitcast [1 x i32]* %payload4 to %"Material::Glass"*
  %3 = getelementptr inbounds %"Material::Glass", %"Material::Glass"* %variant5, i32 0, i32 0
  store float 1.500000e+00, float* %3, align 4
  %4 = load %"enums::Material", %"enums::Material"* %variant2, align 4
  store %"enums::Material" %4, %"enums::Material"* %if.value, align 4
  br label %if.end

if.end:                                           ; preds = %if.else, %cond.true
  %5 = load %"enums::Material", %"enums::Material"* %if.value, align 4
  store %"enums::Material" %5, %"enums::Material"* %m, align 4
  %6 = load %"enums::Material", %"enums::Material"* %m, align 4
  %7 = call float @"enums::albedo"(%"enums::Material" %6)
  call void @"trax::store_f32"(i32 0, float %7)
  ret void

cond.true:                                        ; preds = %start
  %8 = getelementptr inbounds %"enums::Material", %"enums::Material"* %variant, i32 0, i32 1
  store [1 x i32] zeroinitializer, [1 x i32]* %8, align 4
  %tag = getelementptr inbounds %"enums::Material", %"enums::Material"* %variant, i32 0, i32 0
  store i32 0, i32* %tag, align 4
  %payload = getelementptr inbounds %"enums::Material", %"enums::Material"* %variant, i32 0, i32 1
  %variant1 = bitcast [1 x i32]* %payload to %"Material::Diffuse"*
  %9 = getelementptr inbounds %"Material::Diffuse", %"Material::Diffuse"* %variant1, i32 0, i32 0
  store float 2.500000e-01, float* %9, align 4
  %10 = load %"enums::Material", %"enums::Material"* %variant, align 4
  store %"enums::Material" %10, %"enums::Material"* %if.value, align 4
  br label %if.end
}

define internal float @"enums::albedo"(%"enums::Material" %0) {
entry:
  %m = alloca %"enums::Material", align 8
  store %"enums::Material" %0, %"enums::Material"* %m, align 4
  %match.value = alloca float, align 4
  %a = alloca float, align 4
  %ior = alloca float, align 4
  br label %start

start:                                            ; preds = %entry
  %tag = getelementptr inbounds %"enums::Material", %"enums::Material"* %m, i32 0, i32 0
  %tag1 = load i32, i32* %tag, align 4
  %1 = icmp eq i32 %tag1, 0
  br i1 %1, label %pat.ok, label %arm.next

match.end:                                        ; preds = %pat.ok15, %arm.body, %pat.ok5, %pat.ok
  %2 = load float, float* %match.value, align 4
  ret float %2

arm.next:                                         ; preds = %start
  %tag3 = getelementptr inbounds %"enums::Material", %"enums::Material"* %m, i32 0, i32 0
  %tag4 = load i32, i32* %tag3, align 4
  %3 = icmp eq i32 %tag4, 1
  br i1 %3, label %pat.ok5, label %arm.next2

pat.ok:                                           ; preds = %start
  %payload = getelementptr inbounds %"enums::Material", %"enums::Material"* %m, i32 0, i32 1
  %variant = bitcast [1 x i32]* %payload to %"Material::Diffuse"*
  %4 = getelementptr inbounds %"Material::Diffuse", %"Material::Diffuse"* %variant, i32 0, i32 0
  %5 = load float, float* %4, align 4
  store float %5, float* %a, align 4
  %6 = load float, float* %a, align 4
  store float %6, float* %match.value, align 4
  br label %match.end

arm.next2:                                        ; preds = %arm.next
  %tag7 = getelementptr inbounds %"enums::Material", %"enums::Material"* %m, i32 0, i32 0
  %tag8 = load i32, i32* %tag7, align 4
  %7 = icmp eq i32 %tag8, 2
  br i1 %7, label %pat.ok9, label %arm.next6

pat.ok5:                                          ; preds = %arm.next
  store float 1.000000e+00, float* %match.value, align 4
  br label %match.end

arm.next6:                                        ; preds = %pat.ok9, %arm.next2
  %tag13 = getelementptr inbounds %"enums::Material", %"enums::Material"* %m, i32 0, i32 0
  %tag14 = load i32, i32* %tag13, align 4
  %8 = icmp eq i32 %tag14, 2
  br i1 %8, label %pat.ok15, label %arm.next12

pat.ok9:                                          ; preds = %arm.next2
  %payload10 = getelementptr inbounds %"enums::Material", %"enums::Material"* %m, i32 0, i32 1
  %variant11 = bitcast [1 x i32]* %payload10 to %"Material::Glass"*
  %9 = getelementptr inbounds %"Material::Glass", %"Material::Glass"* %variant11, i32 0, i32 0
  %10 = load float, float* %9, align 4
  store float %10, float* %ior, align 4
  %11 = load float, float* %ior, align 4
  %12 = fcmp ogt float %11, 0x3FF6666660000000
  br i1 %12, label %arm.body, label %arm.next6

arm.body:                                         ; preds = %pat.ok9
  store float 0x3FECCCCCC0000000, float* %match.value, align 4
  br label %match.end

arm.next12:                                       ; preds = %arm.next6
  call void asm sideeffect ".set push\0A.set noat\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $0,$$\\r\0A.set .Ltrax_rs_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $0,$$zero\0A.set .Ltrax_rs_${:uid}, 0\0A.endif\0A.ifc $0,$$at\0A.set .Ltrax_rs_${:uid}, 1\0A.endif\0A.ifc $0,$$v0\0A.set .Ltrax_rs_${:uid}, 2\0A.endif\0A.ifc $0,$$v1\0A.set .Ltrax_rs_${:uid}, 3\0A.endif\0A.ifc $0,$$a0\0A.set .Ltrax_rs_${:uid}, 4\0A.endif\0A.ifc $0,$$a1\0A.set .Ltrax_rs_${:uid}, 5\0A.endif\0A.ifc $0,$$a2\0A.set .Ltrax_rs_${:uid}, 6\0A.endif\0A.ifc $0,$$a3\0A.set .Ltrax_rs_${:uid}, 7\0A.endif\0A.ifc $0,$$t0\0A.set .Ltrax_rs_${:uid}, 8\0A.endif\0A.ifc $0,$$t1\0A.set .Ltrax_rs_${:uid}, 9\0A.endif\0A.ifc $0,$$t2\0A.set .Ltrax_rs_${:uid}, 10\0A.endif\0A.ifc $0,$$t3\0A.set .Ltrax_rs_${:uid}, 11\0A.endif\0A.ifc $0,$$t4\0A.set .Ltrax_rs_${:uid}, 12\0A.endif\0A.ifc $0,$$t5\0A.set .Ltrax_rs_${:uid}, 13\0A.endif\0A.ifc $0,$$t6\0A.set .Ltrax_rs_${:uid}, 14\0A.endif\0A.ifc $0,$$t7\0A.set .Ltrax_rs_${:uid}, 15\0A.endif\0A.ifc $0,$$s0\0A.set .Ltrax_rs_${:uid}, 16\0A.endif\0A.ifc $0,$$s1\0A.set .Ltrax_rs_${:uid}, 17\0A.endif\0A.ifc $0,$$s2\0A.set .Ltrax_rs_${:uid}, 18\0A.endif\0A.ifc $0,$$s3\0A.set .Ltrax_rs_${:uid}, 19\0A.endif\0A.ifc $0,$$s4\0A.set .Ltrax_rs_${:uid}, 20\0A.endif\0A.ifc $0,$$s5\0A.set .Ltrax_rs_${:uid}, 21\0A.endif\0A.ifc $0,$$s6\0A.set .Ltrax_rs_${:uid}, 22\0A.endif\0A.ifc $0,$$s7\0A.set .Ltrax_rs_${:uid}, 23\0A.endif\0A.ifc $0,$$t8\0A.set .Ltrax_rs_${:uid}, 24\0A.endif\0A.ifc $0,$$t9\0A.set .Ltrax_rs_${:uid}, 25\0A.endif\0A.ifc $0,$$k0\0A.set .Ltrax_rs_${:uid}, 26\0A.endif\0A.ifc $0,$$k1\0A.set .Ltrax_rs_${:uid}, 27\0A.endif\0A.ifc $0,$$gp\0A.set .Ltrax_rs_${:uid}, 28\0A.endif\0A.ifc $0,$$sp\0A.set .Ltrax_rs_${:uid}, 29\0A.endif\0A.ifc $0,$$fp\0A.set .Ltrax_rs_${:uid}, 30\0A.endif\0A.ifc $0,$$ra\0A.set .Ltrax_rs_${:uid}, 31\0A.endif\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $1,$$\\r\0A.set .Ltrax_rt_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $1,$$zero\0A.set .Ltrax_rt_${:uid}, 0\0A.endif\0A.ifc $1,$$at\0A.set .Ltrax_rt_${:uid}, 1\0A.endif\0A.ifc $1,$$v0\0A.set .Ltrax_rt_${:uid}, 2\0A.endif\0A.ifc $1,$$v1\0A.set .Ltrax_rt_${:uid}, 3\0A.endif\0A.ifc $1,$$a0\0A.set .Ltrax_rt_${:uid}, 4\0A.endif\0A.ifc $1,$$a1\0A.set .Ltrax_rt_${:uid}, 5\0A.endif\0A.ifc $1,$$a2\0A.set .Ltrax_rt_${:uid}, 6\0A.endif\0A.ifc $1,$$a3\0A.set .Ltrax_rt_${:uid}, 7\0A.endif\0A.ifc $1,$$t0\0A.set .Ltrax_rt_${:uid}, 8\0A.endif\0A.ifc $1,$$t1\0A.set .Ltrax_rt_${:uid}, 9\0A.endif\0A.ifc $1,$$t2\0A.set .Ltrax_rt_${:uid}, 10\0A.endif\0A.ifc $1,$$t3\0A.set .Ltrax_rt_${:uid}, 11\0A.endif\0A.ifc $1,$$t4\0A.set .Ltrax_rt_${:uid}, 12\0A.endif\0A.ifc $1,$$t5\0A.set .Ltrax_rt_${:uid}, 13\0A.endif\0A.ifc $1,$$t6\0A.set .Ltrax_rt_${:uid}, 14\0A.endif\0A.ifc $1,$$t7\0A.set .Ltrax_rt_${:uid}, 15\0A.endif\0A.ifc $1,$$s0\0A.set .Ltrax_rt_${:uid}, 16\0A.endif\0A.ifc $1,$$s1\0A.set .Ltrax_rt_${:uid}, 17\0A.endif\0A.ifc $1,$$s2\0A.set .Ltrax_rt_${:uid}, 18\0A.endif\0A.ifc $1,$$s3\0A.set .Ltrax_rt_${:uid}, 19\0A.endif\0A.ifc $1,$$s4\0A.set .Ltrax_rt_${:uid}, 20\0A.endif\0A.ifc $1,$$s5\0A.set .Ltrax_rt_${:uid}, 21\0A.endif\0A.ifc $1,$$s6\0A.set .Ltrax_rt_${:uid}, 22\0A.endif\0A.ifc $1,$$s7\0A.set .Ltrax_rt_${:uid}, 23\0A.endif\0A.ifc $1,$$t8\0A.set .Ltrax_rt_${:uid}, 24\0A.endif\0A.ifc $1,$$t9\0A.set .Ltrax_rt_${:uid}, 25\0A.endif\0A.ifc $1,$$k0\0A.set .Ltrax_rt_${:uid}, 26\0A.endif\0A.ifc $1,$$k1\0A.set .Ltrax_rt_${:uid}, 27\0A.endif\0A.ifc $1,$$gp\0A.set .Ltrax_rt_${:uid}, 28\0A.endif\0A.ifc $1,$$sp\0A.set .Ltrax_rt_${:uid}, 29\0A.endif\0A.ifc $1,$$fp\0A.set .Ltrax_rt_${:uid}, 30\0A.endif\0A.ifc $1,$$ra\0A.set .Ltrax_rt_${:uid}, 31\0A.endif\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $2,$$\\r\0A.set .Ltrax_rd_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $2,$$zero\0A.set .Ltrax_rd_${:uid}, 0\0A.endif\0A.ifc $2,$$at\0A.set .Ltrax_rd_${:uid}, 1\0A.endif\0A.ifc $2,$$v0\0A.set .Ltrax_rd_${:uid}, 2\0A.endif\0A.ifc $2,$$v1\0A.set .Ltrax_rd_${:uid}, 3\0A.endif\0A.ifc $2,$$a0\0A.set .Ltrax_rd_${:uid}, 4\0A.endif\0A.ifc $2,$$a1\0A.set .Ltrax_rd_${:uid}, 5\0A.endif\0A.ifc $2,$$a2\0A.set .Ltrax_rd_${:uid}, 6\0A.endif\0A.ifc $2,$$a3\0A.set .Ltrax_rd_${:uid}, 7\0A.endif\0A.ifc $2,$$t0\0A.set .Ltrax_rd_${:uid}, 8\0A.endif\0A.ifc $2,$$t1\0A.set .Ltrax_rd_${:uid}, 9\0A.endif\0A.ifc $2,$$t2\0A.set .Ltrax_rd_${:uid}, 10\0A.endif\0A.ifc $2,$$t3\0A.set .Ltrax_rd_${:uid}, 11\0A.endif\0A.ifc $2,$$t4\0A.set .Ltrax_rd_${:uid}, 12\0A.endif\0A.ifc $2,$$t5\0A.set .Ltrax_rd_${:uid}, 13\0A.endif\0A.ifc $2,$$t6\0A.set .Ltrax_rd_${:uid}, 14\0A.endif\0A.ifc $2,$$t7\0A.set .Ltrax_rd_${:uid}, 15\0A.endif\0A.ifc $2,$$s0\0A.set .Ltrax_rd_${:uid}, 16\0A.endif\0A.ifc $2,$$s1\0A.set .Ltrax_rd_${:uid}, 17\0A.endif\0A.ifc $2,$$s2\0A.set .Ltrax_rd_${:uid}, 18\0A.endif\0A.ifc $2,$$s3\0A.set .Ltrax_rd_${:uid}, 19\0A.endif\0A.ifc $2,$$s4\0A.set .Ltrax_rd_${:uid}, 20\0A.endif\0A.ifc $2,$$s5\0A.set .Ltrax_rd_${:uid}, 21\0A.endif\0A.ifc $2,$$s6\0A.set .Ltrax_rd_${:uid}, 22\0A.endif\0A.ifc $2,$$s7\0A.set .Ltrax_rd_${:uid}, 23\0A.endif\0A.ifc $2,$$t8\0A.set .Ltrax_rd_${:uid}, 24\0A.endif\0A.ifc $2,$$t9\0A.set .Ltrax_rd_${:uid}, 25\0A.endif\0A.ifc $2,$$k0\0A.set .Ltrax_rd_${:uid}, 26\0A.endif\0A.ifc $2,$$k1\0A.set .Ltrax_rd_${:uid}, 27\0A.endif\0A.ifc $2,$$gp\0A.set .Ltrax_rd_${:uid}, 28\0A.endif\0A.ifc $2,$$sp\0A.set .Ltrax_rd_${:uid}, 29\0A.endif\0A.ifc $2,$$fp\0A.set .Ltrax_rd_${:uid}, 30\0A.endif\0A.ifc $2,$$ra\0A.set .Ltrax_rd_${:uid}, 31\0A.endif\0A.word 0x7000001d | (.Ltrax_rs_${:uid} << 21) | (.Ltrax_rt_${:uid} << 16) | (.Ltrax_rd_${:uid} << 11)\0A.set pop", "r,r,r"(i32 4, i32 ptrtoint ([20 x i8]* @.str.0 to i32), i32 20)
  unreachable

pat.ok15:                                         ; preds = %arm.next6
  store float 5.000000e-01, float* %match.value, align 4
  br label %match.end
}

