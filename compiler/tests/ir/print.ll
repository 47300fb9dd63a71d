define dso_local void @trax_main() {
entry:
  %p = alloca %"print::P", align 8
  %msg.args = alloca [8 x i32], align 4
  br label %start

start:                                            ; preds = %entry
  %0 = call float @"trax::rand"()
  %1 = insertvalue %"print::P" undef, float %0, 0
  %2 = insertvalue %"print::P" %1, i8 3, 1
  store %"print::P" %2, %"print::P"* %p, align 4
  %3 = getelementptr inbounds %"print::P", %"print::P"* %p, i32 0, i32 0
  %4 = load float, float* %3, align 4
  %5 = call i32 @"trax::global_id"()
  %6 = bitcast float %4 to i32
  %7 = ptrtoint %"print::P"* %p to i32
  %8 = getelementptr inbounds [8 x i32], [8 x i32]* %msg.args, i32 0, i32 0
  store i32 ptrtoint ([25 x i8]* @.str.0 to i32), i32* %8, align 4
  %9 = getelementptr inbounds [8 x i32], [8 x i32]* %msg.args, i32 0, i32 1
  store i32 25, i32* %9, align 4
  %10 = getelementptr inbounds [8 x i32], [8 x i32]* %msg.args, i32 0, i32 2
  store i32 %6, i32* %10, align 4
  %11 = getelementptr inbounds [8 x i32], [8 x i32]* %msg.args, i32 0, i32 4
  store i32 %7, i32* %11, align 4
  %12 = getelementptr inbounds [8 x i32], [8 x i32]* %msg.args, i32 0, i32 5
  store i32 ptrtoint ([27 x i8]* @.desc.0 to i32), i32* %12, align 4
  %13 = getelementptr inbounds [8 x i32], [8 x i32]* %msg.args, i32 0, i32 6
  store i32 %5, i32* %13, align 4
  %14 = bitcast [8 x i32]* %msg.args to i32*
  %15 = ptrtoint i32* %14 to i32
  call void asm sideeffect ".set push\0A.set noat\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $0,$$\\r\0A.set .Ltrax_rs_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $0,$$zero\0A.set .Ltrax_rs_${:uid}, 0\0A.endif\0A.ifc $0,$$at\0A.set .Ltrax_rs_${:uid}, 1\0A.endif\0A.ifc $0,$$v0\0A.set .Ltrax_rs_${:uid}, 2\0A.endif\0A.ifc $0,$$v1\0A.set .Ltrax_rs_${:uid}, 3\0A.endif\0A.ifc $0,$$a0\0A.set .Ltrax_rs_${:uid}, 4\0A.endif\0A.ifc $0,$$a1\0A.set .Ltrax_rs_${:uid}, 5\0A.endif\0A.ifc $0,$$a2\0A.set .Ltrax_rs_${:uid}, 6\0A.endif\0A.ifc $0,$$a3\0A.set .Ltrax_rs_${:uid}, 7\0A.endif\0A.ifc $0,$$t0\0A.set .Ltrax_rs_${:uid}, 8\0A.endif\0A.ifc $0,$$t1\0A.set .Ltrax_rs_${:uid}, 9\0A.endif\0A.ifc $0,$$t2\0A.set .Ltrax_rs_${:uid}, 10\0A.endif\0A.ifc $0,$$t3\0A.set .Ltrax_rs_${:uid}, 11\0A.endif\0A.ifc $0,$$t4\0A.set .Ltrax_rs_${:uid}, 12\0A.endif\0A.ifc $0,$$t5\0A.set .Ltrax_rs_${:uid}, 13\0A.endif\0A.ifc $0,$$t6\0A.set .Ltrax_rs_${:uid}, 14\0A.endif\0A.ifc $0,$$t7\0A.set .Ltrax_rs_${:uid}, 15\0A.endif\0A.ifc $0,$$s0\0A.set .Ltrax_rs_${:uid}, 16\0A.endif\0A.ifc $0,$$s1\0A.set .Ltrax_rs_${:uid}, 17\0A.endif\0A.ifc $0,$$s2\0A.set .Ltrax_rs_${:uid}, 18\0A.endif\0A.ifc $0,$$s3\0A.set .Ltrax_rs_${:uid}, 19\0A.endif\0A.ifc $0,$$s4\0A.set .Ltrax_rs_${:uid}, 20\0A.endif\0A.ifc $0,$$s5\0A.set .Ltrax_rs_${:uid}, 21\0A.endif\0A.ifc $0,$$s6\0A.set .Ltrax_rs_${:uid}, 22\0A.endif\0A.ifc $0,$$s7\0A.set .Ltrax_rs_${:uid}, 23\0A.endif\0A.ifc $0,$$t8\0A.set .Ltrax_rs_${:uid}, 24\0A.endif\0A.ifc $0,$$t9\0A.set .Ltrax_rs_${:uid}, 25\0A.endif\0A.ifc $0,$$k0\0A.set .Ltrax_rs_${:uid}, 26\0A.endif\0A.ifc $0,$$k1\0A.set .Ltrax_rs_${:uid}, 27\0A.endif\0A.ifc $0,$$gp\0A.set .Ltrax_rs_${:uid}, 28\0A.endif\0A.ifc $0,$$sp\0A.set .Ltrax_rs_${:uid}, 29\0A.endif\0A.ifc $0,$$fp\0A.set .Ltrax_rs_${:uid}, 30\0A.endif\0A.ifc $0,$$ra\0A.set .Ltrax_rs_${:uid}, 31\0A.endif\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $1,$$\\r\0A.set .Ltrax_rt_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $1,$$zero\0A.set .Ltrax_rt_${:uid}, 0\0A.endif\0A.ifc $1,$$at\0A.set .Ltrax_rt_${:uid}, 1\0A.endif\0A.ifc $1,$$v0\0A.set .Ltrax_rt_${:uid}, 2\0A.endif\0A.ifc $1,$$v1\0A.set .Ltrax_rt_${:uid}, 3\0A.endif\0A.ifc $1,$$a0\0A.set .Ltrax_rt_${:uid}, 4\0A.endif\0A.ifc $1,$$a1\0A.set .Ltrax_rt_${:uid}, 5\0A.endif\0A.ifc $1,$$a2\0A.set .Ltrax_rt_${:uid}, 6\0A.endif\0A.ifc $1,$$a3\0A.set .Ltrax_rt_${:uid}, 7\0A.endif\0A.ifc $1,$$t0\0A.set .Ltrax_rt_${:uid}, 8\0A.endif\0A.ifc $1,$$t1\0A.set .Ltrax_rt_${:uid}, 9\0A.endif\0A.ifc $1,$$t2\0A.set .Ltrax_rt_${:uid}, 10\0A.endif\0A.ifc $1,$$t3\0A.set .Ltrax_rt_${:uid}, 11\0A.endif\0A.ifc $1,$$t4\0A.set .Ltrax_rt_${:uid}, 12\0A.endif\0A.ifc $1,$$t5\0A.set .Ltrax_rt_${:uid}, 13\0A.endif\0A.ifc $1,$$t6\0A.set .Ltrax_rt_${:uid}, 14\0A.endif\0A.ifc $1,$$t7\0A.set .Ltrax_rt_${:uid}, 15\0A.endif\0A.ifc $1,$$s0\0A.set .Ltrax_rt_${:uid}, 16\0A.endif\0A.ifc $1,$$s1\0A.set .Ltrax_rt_${:uid}, 17\0A.endif\0A.ifc $1,$$s2\0A.set .Ltrax_rt_${:uid}, 18\0A.endif\0A.ifc $1,$$s3\0A.set .Ltrax_rt_${:uid}, 19\0A.endif\0A.ifc $1,$$s4\0A.set .Ltrax_rt_${:uid}, 20\0A.endif\0A.ifc $1,$$s5\0A.set .Ltrax_rt_${:uid}, 21\0A.endif\0A.ifc $1,$$s6\0A.set .Ltrax_rt_${:uid}, 22\0A.endif\0A.ifc $1,$$s7\0A.set .Ltrax_rt_${:uid}, 23\0A.endif\0A.ifc $1,$$t8\0A.set .Ltrax_rt_${:uid}, 24\0A.endif\0A.ifc $1,$$t9\0A.set .Ltrax_rt_${:uid}, 25\0A.endif\0A.ifc $1,$$k0\0A.set .Ltrax_rt_${:uid}, 26\0A.endif\0A.ifc $1,$$k1\0A.set .Ltrax_rt_${:uid}, 27\0A.endif\0A.ifc $1,$$gp\0A.set .Ltrax_rt_${:uid}, 28\0A.endif\0A.ifc $1,$$sp\0A.set .Ltrax_rt_${:uid}, 29\0A.endif\0A.ifc $1,$$fp\0A.set .Ltrax_rt_${:uid}, 30\0A.endif\0A.ifc $1,$$ra\0A.set .Ltrax_rt_${:uid}, 31\0A.endif\0A.word 0x7000001f | (.Ltrax_rs_${:uid} << 21) | (.Ltrax_rt_${:uid} << 16)\0A.set pop", "r,r"(i32 %15, i32 32)
  ret void
}

