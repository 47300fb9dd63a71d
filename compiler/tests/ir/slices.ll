define dso_local void @trax_main() {
entry:
  %a = alloca [4 x float], align 4
  %k = alloca i32, align 4
  %msg.args = alloca [6 x i32], align 4
  br label %start

start:                                            ; preds = %entry
  store [4 x float] [float 1.000000e+00, float 2.000000e+00, float 3.000000e+00, float 4.000000e+00], [4 x float]* %a, align 4
  %0 = call i32 @"trax::global_id"()
  store i32 %0, i32* %k, align 4
  %1 = load i32, i32* %k, align 4
  %2 = icmp ule i32 %1, 4
  br i1 %2, label %check.ok, label %check.fail

check.fail:                                       ; preds = %start
  %3 = getelementptr inbounds [6 x i32], [6 x i32]* %msg.args, i32 0, i32 0
  store i32 ptrtoint ([60 x i8]* @.str.0 to i32), i32* %3, align 4
  %4 = getelementptr inbounds [6 x i32], [6 x i32]* %msg.args, i32 0, i32 1
  store i32 60, i32* %4, align 4
  %5 = getelementptr inbounds [6 x i32], [6 x i32]* %msg.args, i32 0, i32 2
  store i32 %1, i32* %5, align 4
  %6 = getelementptr inbounds [6 x i32], [6 x i32]* %msg.args, i32 0, i32 4
  store i32 4, i32* %6, align 4
  %7 = bitcast [6 x i32]* %msg.args to i32*
  %8 = ptrtoint i32* %7 to i32
  call void asm sideeffect ".set push\0A.set noat\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $0,$$\\r\0A.set .Ltrax_rs_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $0,$$zero\0A.set .Ltrax_rs_${:uid}, 0\0A.endif\0A.ifc $0,$$at\0A.set .Ltrax_rs_${:uid}, 1\0A.endif\0A.ifc $0,$$v0\0A.set .Ltrax_rs_${:uid}, 2\0A.endif\0A.ifc $0,$$v1\0A.set .Ltrax_rs_${:uid}, 3\0A.endif\0A.ifc $0,$$a0\0A.set .Ltrax_rs_${:uid}, 4\0A.endif\0A.ifc $0,$$a1\0A.set .Ltrax_rs_${:uid}, 5\0A.endif\0A.ifc $0,$$a2\0A.set .Ltrax_rs_${:uid}, 6\0A.endif\0A.ifc $0,$$a3\0A.set .Ltrax_rs_${:uid}, 7\0A.endif\0A.ifc $0,$$t0\0A.set .Ltrax_rs_${:uid}, 8\0A.endif\0A.ifc $0,$$t1\0A.set .Ltrax_rs_${:uid}, 9\0A.endif\0A.ifc $0,$$t2\0A.set .Ltrax_rs_${:uid}, 10\0A.endif\0A.ifc $0,$$t3\0A.set .Ltrax_rs_${:uid}, 11\0A.endif\0A.ifc $0,$$t4\0A.set .Ltrax_rs_${:uid}, 12\0A.endif\0A.ifc $0,$$t5\0A.set .Ltrax_rs_${:uid}, 13\0A.endif\0A.ifc $0,$$t6\0A.set .Ltrax_rs_${:uid}, 14\0A.endif\0A.ifc $0,$$t7\0A.set .Ltrax_rs_${:uid}, 15\0A.endif\0A.ifc $0,$$s0\0A.set .Ltrax_rs_${:uid}, 16\0A.endif\0A.ifc $0,$$s1\0A.set .Ltrax_rs_${:uid}, 17\0A.endif\0A.ifc $0,$$s2\0A.set .Ltrax_rs_${:uid}, 18\0A.endif\0A.ifc $0,$$s3\0A.set .Ltrax_rs_${:uid}, 19\0A.endif\0A.ifc $0,$$s4\0A.set .Ltrax_rs_${:uid}, 20\0A.endif\0A.ifc $0,$$s5\0A.set .Ltrax_rs_${:uid}, 21\0A.endif\0A.ifc $0,$$s6\0A.set .Ltrax_rs_${:uid}, 22\0A.endif\0A.ifc $0,$$s7\0A.set .Ltrax_rs_${:uid}, 23\0A.endif\0A.ifc $0,$$t8\0A.set .Ltrax_rs_${:uid}, 24\0A.endif\0A.ifc $0,$$t9\0A.set .Ltrax_rs_${:uid}, 25\0A.endif\0A.ifc $0,$$k0\0A.set .Ltrax_rs_${:uid}, 26\0A.endif\0A.ifc $0,$$k1\0A.set .Ltrax_rs_${:uid}, 27\0A.endif\0A.ifc $0,$$gp\0A.set .Ltrax_rs_${:uid}, 28\0A.endif\0A.ifc $0,$$sp\0A.set .Ltrax_rs_${:uid}, 29\0A.endif\0A.ifc $0,$$fp\0A.set .Ltrax_rs_${:uid}, 30\0A.endif\0A.ifc $0,$$ra\0A.set .Ltrax_rs_${:uid}, 31\0A.endif\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $1,$$\\r\0A.set .Ltrax_rt_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $1,$$zero\0A.set .Ltrax_rt_${:uid}, 0\0A.endif\0A.ifc $1,$$at\0A.set .Ltrax_rt_${:uid}, 1\0A.endif\0A.ifc $1,$$v0\0A.set .Ltrax_rt_${:uid}, 2\0A.endif\0A.ifc $1,$$v1\0A.set .Ltrax_rt_${:uid}, 3\0A.endif\0A.ifc $1,$$a0\0A.set .Ltrax_rt_${:uid}, 4\0A.endif\0A.ifc $1,$$a1\0A.set .Ltrax_rt_${:uid}, 5\0A.endif\0A.ifc $1,$$a2\0A.set .Ltrax_rt_${:uid}, 6\0A.endif\0A.ifc $1,$$a3\0A.set .Ltrax_rt_${:uid}, 7\0A.endif\0A.ifc $1,$$t0\0A.set .Ltrax_rt_${:uid}, 8\0A.endif\0A.ifc $1,$$t1\0A.set .Ltrax_rt_${:uid}, 9\0A.endif\0A.ifc $1,$$t2\0A.set .Ltrax_rt_${:uid}, 10\0A.endif\0A.ifc $1,$$t3\0A.set .Ltrax_rt_${:uid}, 11\0A.endif\0A.ifc $1,$$t4\0A.set .Ltrax_rt_${:uid}, 12\0A.endif\0A.ifc $1,$$t5\0A.set .Ltrax_rt_${:uid}, 13\0A.endif\0A.ifc $1,$$t6\0A.set .Ltrax_rt_${:uid}, 14\0A.endif\0A.ifc $1,$$t7\0A.set .Ltrax_rt_${:uid}, 15\0A.endif\0A.ifc $1,$$s0\0A.set .Ltrax_rt_${:uid}, 16\0A.endif\0A.ifc $1,$$s1\0A.set .Ltrax_rt_${:uid}, 17\0A.endif\0A.ifc $1,$$s2\0A.set .Ltrax_rt_${:uid}, 18\0A.endif\0A.ifc $1,$$s3\0A.set .Ltrax_rt_${:uid}, 19\0A.endif\0A.ifc $1,$$s4\0A.set .Ltrax_rt_${:uid}, 20\0A.endif\0A.ifc $1,$$s5\0A.set .Ltrax_rt_${:uid}, 21\0A.endif\0A.ifc $1,$$s6\0A.set .Ltrax_rt_${:uid}, 22\0A.endif\0A.ifc $1,$$s7\0A.set .Ltrax_rt_${:uid}, 23\0A.endif\0A.ifc $1,$$t8\0A.set .Ltrax_rt_${:uid}, 24\0A.endif\0A.ifc $1,$$t9\0A.set .Ltrax_rt_${:uid}, 25\0A.endif\0A.ifc $1,$$k0\0A.set .Ltrax_rt_${:uid}, 26\0A.endif\0A.ifc $1,$$k1\0A.set .Ltrax_rt_${:uid}, 27\0A.endif\0A.ifc $1,$$gp\0A.set .Ltrax_rt_${:uid}, 28\0A.endif\0A.ifc $1,$$sp\0A.set .Ltrax_rt_${:uid}, 29\0A.endif\0A.ifc $1,$$fp\0A.set .Ltrax_rt_${:uid}, 30\0A.endif\0A.ifc $1,$$ra\0A.set .Ltrax_rt_${:uid}, 31\0A.endif\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $2,$$\\r\0A.set .Ltrax_rd_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $2,$$zero\0A.set .Ltrax_rd_${:uid}, 0\0A.endif\0A.ifc $2,$$at\0A.set .Ltrax_rd_${:uid}, 1\0A.endif\0A.ifc $2,$$v0\0A.set .Ltrax_rd_${:uid}, 2\0A.endif\0A.ifc $2,$$v1\0A.set .Ltrax_rd_${:uid}, 3\0A.endif\0A.ifc $2,$$a0\0A.set .Ltrax_rd_${:uid}, 4\0A.endif\0A.ifc $2,$$a1\0A.set .Ltrax_rd_${:uid}, 5\0A.endif\0A.ifc $2,$$a2\0A.set .Ltrax_rd_${:uid}, 6\0A.endif\0A.ifc $2,$$a3\0A.set .Ltrax_rd_${:uid}, 7\0A.endif\0A.ifc $2,$$t0\0A.set .Ltrax_rd_${:uid}, 8\0A.endif\0A.ifc $2,$$t1\0A.set .Ltrax_rd_${:uid}, 9\0A.endif\0A.ifc $2,$$t2\0A.set .Ltrax_rd_${:uid}, 10\0A.endif\0A.ifc $2,$$t3\0A.set .Ltrax_rd_${:uid}, 11\0A.endif\0A.ifc $2,$$t4\0A.set .Ltrax_rd_${:uid}, 12\0A.endif\0A.ifc $2,$$t5\0A.set .Ltrax_rd_${:uid}, 13\0A.endif\0A.ifc $2,$$t6\0A.set .Ltrax_rd_${:uid}, 14\0A.endif\0A.ifc $2,$$t7\0A.set .Ltrax_rd_${:uid}, 15\0A.endif\0A.ifc $2,$$s0\0A.set .Ltrax_rd_${:uid}, 16\0A.endif\0A.ifc $2,$$s1\0A.set .Ltrax_rd_${:uid}, 17\0A.endif\0A.ifc $2,$$s2\0A.set .Ltrax_rd_${:uid}, 18\0A.endif\0A.ifc $2,$$s3\0A.set .Ltrax_rd_${:uid}, 19\0A.endif\0A.ifc $2,$$s4\0A.set .Ltrax_rd_${:uid}, 20\0A.endif\0A.ifc $2,$$s5\0A.set .Ltrax_rd_${:uid}, 21\0A.endif\0A.ifc $2,$$s6\0A.set .Ltrax_rd_${:uid}, 22\0A.endif\0A.ifc $2,$$s7\0A.set .Ltrax_rd_${:uid}, 23\0A.endif\0A.ifc $2,$$t8\0A.set .Ltrax_rd_${:uid}, 24\0A.endif\0A.ifc $2,$$t9\0A.set .Ltrax_rd_${:uid}, 25\0A.endif\0A.ifc $2,$$k0\0A.set .Ltrax_rd_${:uid}, 26\0A.endif\0A.ifc $2,$$k1\0A.set .Ltrax_rd_${:uid}, 27\0A.endif\0A.ifc $2,$$gp\0A.set .Ltrax_rd_${:uid}, 28\0A.endif\0A.ifc $2,$$sp\0A.set .Ltrax_rd_${:uid}, 29\0A.endif\0A.ifc $2,$$fp\0A.set .Ltrax_rd_${:uid}, 30\0A.endif\0A.ifc $2,$$ra\0A.set .Ltrax_rd_${:uid}, 31\0A.endif\0A.word 0x7000001d | (.Ltrax_rs_${:uid} << 21) | (.Ltrax_rt_${:uid} << 16) | (.Ltrax_rd_${:uid} << 11)\0A.set pop", "r,r,r"(i32 257, i32 %8, i32 24)
  unreachable

check.ok:                                         ; preds = %start
  %9 = icmp ule i32 0, %1
  br i1 %9, label %check.ok2, label %check.fail1

check.fail1:                                      ; preds = %check.ok
  %10 = getelementptr inbounds [6 x i32], [6 x i32]* %msg.args, i32 0, i32 0
  store i32 ptrtoint ([45 x i8]* @.str.1 to i32), i32* %10, align 4
  %11 = getelementptr inbounds [6 x i32], [6 x i32]* %msg.args, i32 0, i32 1
  store i32 45, i32* %11, align 4
  %12 = getelementptr inbounds [6 x i32], [6 x i32]* %msg.args, i32 0, i32 2
  store i32 0, i32* %12, align 4
  %13 = getelementptr inbounds [6 x i32], [6 x i32]* %msg.args, i32 0, i32 4
  store i32 %1, i32* %13, align 4
  %14 = bitcast [6 x i32]* %msg.args to i32*
  %15 = ptrtoint i32* %14 to i32
  call void asm sideeffect ".set push\0A.set noat\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $0,$$\\r\0A.set .Ltrax_rs_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $0,$$zero\0A.set .Ltrax_rs_${:uid}, 0\0A.endif\0A.ifc $0,$$at\0A.set .Ltrax_rs_${:uid}, 1\0A.endif\0A.ifc $0,$$v0\0A.set .Ltrax_rs_${:uid}, 2\0A.endif\0A.ifc $0,$$v1\0A.set .Ltrax_rs_${:uid}, 3\0A.endif\0A.ifc $0,$$a0\0A.set .Ltrax_rs_${:uid}, 4\0A.endif\0A.ifc $0,$$a1\0A.set .Ltrax_rs_${:uid}, 5\0A.endif\0A.ifc $0,$$a2\0A.set .Ltrax_rs_${:uid}, 6\0A.endif\0A.ifc $0,$$a3\0A.set .Ltrax_rs_${:uid}, 7\0A.endif\0A.ifc $0,$$t0\0A.set .Ltrax_rs_${:uid}, 8\0A.endif\0A.ifc $0,$$t1\0A.set .Ltrax_rs_${:uid}, 9\0A.endif\0A.ifc $0,$$t2\0A.set .Ltrax_rs_${:uid}, 10\0A.endif\0A.ifc $0,$$t3\0A.set .Ltrax_rs_${:uid}, 11\0A.endif\0A.ifc $0,$$t4\0A.set .Ltrax_rs_${:uid}, 12\0A.endif\0A.ifc $0,$$t5\0A.set .Ltrax_rs_${:uid}, 13\0A.endif\0A.ifc $0,$$t6\0A.set .Ltrax_rs_${:uid}, 14\0A.endif\0A.ifc $0,$$t7\0A.set .Ltrax_rs_${:uid}, 15\0A.endif\0A.ifc $0,$$s0\0A.set .Ltrax_rs_${:uid}, 16\0A.endif\0A.ifc $0,$$s1\0A.set .Ltrax_rs_${:uid}, 17\0A.endif\0A.ifc $0,$$s2\0A.set .Ltrax_rs_${:uid}, 18\0A.endif\0A.ifc $0,$$s3\0A.set .Ltrax_rs_${:uid}, 19\0A.endif\0A.ifc $0,$$s4\0A.set .Ltrax_rs_${:uid}, 20\0A.endif\0A.ifc $0,$$s5\0A.set .Ltrax_rs_${:uid}, 21\0A.endif\0A.ifc $0,$$s6\0A.set .Ltrax_rs_${:uid}, 22\0A.endif\0A.ifc $0,$$s7\0A.set .Ltrax_rs_${:uid}, 23\0A.endif\0A.ifc $0,$$t8\0A.set .Ltrax_rs_${:uid}, 24\0A.endif\0A.ifc $0,$$t9\0A.set .Ltrax_rs_${:uid}, 25\0A.endif\0A.ifc $0,$$k0\0A.set .Ltrax_rs_${:uid}, 26\0A.endif\0A.ifc $0,$$k1\0A.set .Ltrax_rs_${:uid}, 27\0A.endif\0A.ifc $0,$$gp\0A.set .Ltrax_rs_${:uid}, 28\0A.endif\0A.ifc $0,$$sp\0A.set .Ltrax_rs_${:uid}, 29\0A.endif\0A.ifc $0,$$fp\0A.set .Ltrax_rs_${:uid}, 30\0A.endif\0A.ifc $0,$$ra\0A.set .Ltrax_rs_${:uid}, 31\0A.endif\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $1,$$\\r\0A.set .Ltrax_rt_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $1,$$zero\0A.set .Ltrax_rt_${:uid}, 0\0A.endif\0A.ifc $1,$$at\0A.set .Ltrax_rt_${:uid}, 1\0A.endif\0A.ifc $1,$$v0\0A.set .Ltrax_rt_${:uid}, 2\0A.endif\0A.ifc $1,$$v1\0A.set .Ltrax_rt_${:uid}, 3\0A.endif\0A.ifc $1,$$a0\0A.set .Ltrax_rt_${:uid}, 4\0A.endif\0A.ifc $1,$$a1\0A.set .Ltrax_rt_${:uid}, 5\0A.endif\0A.ifc $1,$$a2\0A.set .Ltrax_rt_${:uid}, 6\0A.endif\0A.ifc $1,$$a3\0A.set .Ltrax_rt_${:uid}, 7\0A.endif\0A.ifc $1,$$t0\0A.set .Ltrax_rt_${:uid}, 8\0A.endif\0A.ifc $1,$$t1\0A.set .Ltrax_rt_${:uid}, 9\0A.endif\0A.ifc $1,$$t2\0A.set .Ltrax_rt_${:uid}, 10\0A.endif\0A.ifc $1,$$t3\0A.set .Ltrax_rt_${:uid}, 11\0A.endif\0A.ifc $1,$$t4\0A.set .Ltrax_rt_${:uid}, 12\0A.endif\0A.ifc $1,$$t5\0A.set .Ltrax_rt_${:uid}, 13\0A.endif\0A.ifc $1,$$t6\0A.set .Ltrax_rt_${:uid}, 14\0A.endif\0A.ifc $1,$$t7\0A.set .Ltrax_rt_${:uid}, 15\0A.endif\0A.ifc $1,$$s0\0A.set .Ltrax_rt_${:uid}, 16\0A.endif\0A.ifc $1,$$s1\0A.set .Ltrax_rt_${:uid}, 17\0A.endif\0A.ifc $1,$$s2\0A.set .Ltrax_rt_${:uid}, 18\0A.endif\0A.ifc $1,$$s3\0A.set .Ltrax_rt_${:uid}, 19\0A.endif\0A.ifc $1,$$s4\0A.set .Ltrax_rt_${:uid}, 20\0A.endif\0A.ifc $1,$$s5\0A.set .Ltrax_rt_${:uid}, 21\0A.endif\0A.ifc $1,$$s6\0A.set .Ltrax_rt_${:uid}, 22\0A.endif\0A.ifc $1,$$s7\0A.set .Ltrax_rt_${:uid}, 23\0A.endif\0A.ifc $1,$$t8\0A.set .Ltrax_rt_${:uid}, 24\0A.endif\0A.ifc $1,$$t9\0A.set .Ltrax_rt_${:uid}, 25\0A.endif\0A.ifc $1,$$k0\0A.set .Ltrax_rt_${:uid}, 26\0A.endif\0A.ifc $1,$$k1\0A.set .Ltrax_rt_${:uid}, 27\0A.endif\0A.ifc $1,$$gp\0A.set .Ltrax_rt_${:uid}, 28\0A.endif\0A.ifc $1,$$sp\0A.set .Ltrax_rt_${:uid}, 29\0A.endif\0A.ifc $1,$$fp\0A.set .Ltrax_rt_${:uid}, 30\0A.endif\0A.ifc $1,$$ra\0A.set .Ltrax_rt_${:uid}, 31\0A.endif\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $2,$$\\r\0A.set .Ltrax_rd_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $2,$$zero\0A.set .Ltrax_rd_${:uid}, 0\0A.endif\0A.ifc $2,$$at\0A.set .Ltrax_rd_${:uid}, 1\0A.endif\0A.ifc $2,$$v0\0A.set .Ltrax_rd_${:uid}, 2\0A.endif\0A.ifc $2,$$v1\0A.set .Ltrax_rd_${:uid}, 3\0A.endif\0A.ifc $2,$$a0\0A.set .Ltrax_rd_${:uid}, 4\0A.endif\0A.ifc $2,$$a1\0A.set .Ltrax_rd_${:uid}, 5\0A.endif\0A.ifc $2,$$a2\0A.set .Ltrax_rd_${:uid}, 6\0A.endif\0A.ifc $2,$$a3\0A.set .Ltrax_rd_${:uid}, 7\0A.endif\0A.ifc $2,$$t0\0A.set .Ltrax_rd_${:uid}, 8\0A.endif\0A.ifc $2,$$t1\0A.set .Ltrax_rd_${:uid}, 9\0A.endif\0A.ifc $2,$$t2\0A.set .Ltrax_rd_${:uid}, 10\0A.endif\0A.ifc $2,$$t3\0A.set .Ltrax_rd_${:uid}, 11\0A.endif\0A.ifc $2,$$t4\0A.set .Ltrax_rd_${:uid}, 12\0A.endif\0A.ifc $2,$$t5\0A.set .Ltrax_rd_${:uid}, 13\0A.endif\0A.ifc $2,$$t6\0A.set .Ltrax_rd_${:uid}, 14\0A.endif\0A.ifc $2,$$t7\0A.set .Ltrax_rd_${:uid}, 15\0A.endif\0A.ifc $2,$$s0\0A.set .Ltrax_rd_${:uid}, 16\0A.endif\0A.ifc $2,$$s1\0A.set .Ltrax_rd_${:uid}, 17\0A.endif\0A.ifc $2,$$s2\0A.set .Ltrax_rd_${:uid}, 18\0A.endif\0A.ifc $2,$$s3\0A.set .Ltrax_rd_${:uid}, 19\0A.endif\0A.ifc $2,$$s4\0A.set .Ltrax_rd_${:uid}, 20\0A.endif\0A.ifc $2,$$s5\0A.set .Ltrax_rd_${:uid}, 21\0A.endif\0A.ifc $2,$$s6\0A.set .Ltrax_rd_${:uid}, 22\0A.endif\0A.ifc $2,$$s7\0A.set .Ltrax_rd_${:uid}, 23\0A.endif\0A.ifc $2,$$t8\0A.set .Ltrax_rd_${:uid}, 24\0A.endif\0A.ifc $2,$$t9\0A.set .Ltrax_rd_${:uid}, 25\0A.endif\0A.ifc $2,$$k0\0A.set .Ltrax_rd_${:uid}, 26\0A.endif\0A.ifc $2,$$k1\0A.set .Ltrax_rd_${:uid}, 27\0A.endif\0A.ifc $2,$$gp\0A.set .Ltrax_rd_${:uid}, 28\0A.endif\0A.ifc $2,$$sp\0A.set .Ltrax_rd_${:uid}, 29\0A.endif\0A.ifc $2,$$fp\0A.set .Ltrax_rd_${:uid}, 30\0A.endif\0A.ifc $2,$$ra\0A.set .Ltrax_rd_${:uid}, 31\0A.endif\0A.word 0x7000001d | (.Ltrax_rs_${:uid} << 21) | (.Ltrax_rt_${:uid} << 16) | (.Ltrax_rd_${:uid} << 11)\0A.set pop", "r,r,r"(i32 257, i32 %15, i32 24)
  unreachable

check.ok2:                                        ; preds = %check.ok
  %16 = getelementptr inbounds [4 x float], [4 x float]* %a, i32 0, i32 0
  %17 = sub i32 %1, 0
  %18 = insertvalue { float*, i32 } undef, float* %16, 0
  %19 = insertvalue { float*, i32 } %18, i32 %17, 1
  %20 = call float @"slices::sum"({ float*, i32 } %19)
  %21 = load i32, i32* %k, align 4
  %inbounds = icmp ult i32 %21, 4
  br i1 %inbounds, label %check.ok4, label %check.fail3

check.fail3:                                      ; preds = %check.ok2
  %22 = getelementptr inbounds [6 x i32], [6 x i32]* %msg.args, i32 0, i32 0
  store i32 ptrtoint ([56 x i8]* @.str.2 to i32), i32* %22, align 4
  %23 = getelementptr inbounds [6 x i32], [6 x i32]* %msg.args, i32 0, i32 1
  store i32 56, i32* %23, align 4
  %24 = getelementptr inbounds [6 x i32], [6 x i32]* %msg.args, i32 0, i32 2
  store i32 %21, i32* %24, align 4
  %25 = bitcast [6 x i32]* %msg.args to i32*
  %26 = ptrtoint i32* %25 to i32
  call void asm sideeffect ".set push\0A.set noat\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $0,$$\\r\0A.set .Ltrax_rs_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $0,$$zero\0A.set .Ltrax_rs_${:uid}, 0\0A.endif\0A.ifc $0,$$at\0A.set .Ltrax_rs_${:uid}, 1\0A.endif\0A.ifc $0,$$v0\0A.set .Ltrax_rs_${:uid}, 2\0A.endif\0A.ifc $0,$$v1\0A.set .Ltrax_rs_${:uid}, 3\0A.endif\0A.ifc $0,$$a0\0A.set .Ltrax_rs_${:uid}, 4\0A.endif\0A.ifc $0,$$a1\0A.set .Ltrax_rs_${:uid}, 5\0A.endif\0A.ifc $0,$$a2\0A.set .Ltrax_rs_${:uid}, 6\0A.endif\0A.ifc $0,$$a3\0A.set .Ltrax_rs_${:uid}, 7\0A.endif\0A.ifc $0,$$t0\0A.set .Ltrax_rs_${:uid}, 8\0A.endif\0A.ifc $0,$$t1\0A.set .Ltrax_rs_${:uid}, 9\0A.endif\0A.ifc $0,$$t2\0A.set .Ltrax_rs_${:uid}, 10\0A.endif\0A.ifc $0,$$t3\0A.set .Ltrax_rs_${:uid}, 11\0A.endif\0A.ifc $0,$$t4\0A.set .Ltrax_rs_${:uid}, 12\0A.endif\0A.ifc $0,$$t5\0A.set .Ltrax_rs_${:uid}, 13\0A.endif\0A.ifc $0,$$t6\0A.set .Ltrax_rs_${:uid}, 14\0A.endif\0A.ifc $0,$$t7\0A.set .Ltrax_rs_${:uid}, 15\0A.endif\0A.ifc $0,$$s0\0A.set .Ltrax_rs_${:uid}, 16\0A.endif\0A.ifc $0,$$s1\0A.set .Ltrax_rs_${:uid}, 17\0A.endif\0A.ifc $0,$$s2\0A.set .Ltrax_rs_${:uid}, 18\0A.endif\0A.ifc $0,$$s3\0A.set .Ltrax_rs_${:uid}, 19\0A.endif\0A.ifc $0,$$s4\0A.set .Ltrax_rs_${:uid}, 20\0A.endif\0A.ifc $0,$$s5\0A.set .Ltrax_rs_${:uid}, 21\0A.endif\0A.ifc $0,$$s6\0A.set .Ltrax_rs_${:uid}, 22\0A.endif\0A.ifc $0,$$s7\0A.set .Ltrax_rs_${:uid}, 23\0A.endif\0A.ifc $0,$$t8\0A.set .Ltrax_rs_${:uid}, 24\0A.endif\0A.ifc $0,$$t9\0A.set .Ltrax_rs_${:uid}, 25\0A.endif\0A.ifc $0,$$k0\0A.set .Ltrax_rs_${:uid}, 26\0A.endif\0A.ifc $0,$$k1\0A.set .Ltrax_rs_${:uid}, 27\0A.endif\0A.ifc $0,$$gp\0A.set .Ltrax_rs_${:uid}, 28\0A.endif\0A.ifc $0,$$sp\0A.set .Ltrax_rs_${:uid}, 29\0A.endif\0A.ifc $0,$$fp\0A.set .Ltrax_rs_${:uid}, 30\0A.endif\0A.ifc $0,$$ra\0A.set .Ltrax_rs_${:uid}, 31\0A.endif\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $1,$$\\r\0A.set .Ltrax_rt_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $1,$$zero\0A.set .Ltrax_rt_${:uid}, 0\0A.endif\0A.ifc $1,$$at\0A.set .Ltrax_rt_${:uid}, 1\0A.endif\0A.ifc $1,$$v0\0A.set .Ltrax_rt_${:uid}, 2\0A.endif\0A.ifc $1,$$v1\0A.set .Ltrax_rt_${:uid}, 3\0A.endif\0A.ifc $1,$$a0\0A.set .Ltrax_rt_${:uid}, 4\0A.endif\0A.ifc $1,$$a1\0A.set .Ltrax_rt_${:uid}, 5\0A.endif\0A.ifc $1,$$a2\0A.set .Ltrax_rt_${:uid}, 6\0A.endif\0A.ifc $1,$$a3\0A.set .Ltrax_rt_${:uid}, 7\0A.endif\0A.ifc $1,$$t0\0A.set .Ltrax_rt_${:uid}, 8\0A.endif\0A.ifc $1,$$t1\0A.set .Ltrax_rt_${:uid}, 9\0A.endif\0A.ifc $1,$$t2\0A.set .Ltrax_rt_${:uid}, 10\0A.endif\0A.ifc $1,$$t3\0A.set .Ltrax_rt_${:uid}, 11\0A.endif\0A.ifc $1,$$t4\0A.set .Ltrax_rt_${:uid}, 12\0A.endif\0A.ifc $1,$$t5\0A.set .Ltrax_rt_${:uid}, 13\0A.endif\0A.ifc $1,$$t6\0A.set .Ltrax_rt_${:uid}, 14\0A.endif\0A.ifc $1,$$t7\0A.set .Ltrax_rt_${:uid}, 15\0A.endif\0A.ifc $1,$$s0\0A.set .Ltrax_rt_${:uid}, 16\0A.endif\0A.ifc $1,$$s1\0A.set .Ltrax_rt_${:uid}, 17\0A.endif\0A.ifc $1,$$s2\0A.set .Ltrax_rt_${:uid}, 18\0A.endif\0A.ifc $1,$$s3\0A.set .Ltrax_rt_${:uid}, 19\0A.endif\0A.ifc $1,$$s4\0A.set .Ltrax_rt_${:uid}, 20\0A.endif\0A.ifc $1,$$s5\0A.set .Ltrax_rt_${:uid}, 21\0A.endif\0A.ifc $1,$$s6\0A.set .Ltrax_rt_${:uid}, 22\0A.endif\0A.ifc $1,$$s7\0A.set .Ltrax_rt_${:uid}, 23\0A.endif\0A.ifc $1,$$t8\0A.set .Ltrax_rt_${:uid}, 24\0A.endif\0A.ifc $1,$$t9\0A.set .Ltrax_rt_${:uid}, 25\0A.endif\0A.ifc $1,$$k0\0A.set .Ltrax_rt_${:uid}, 26\0A.endif\0A.ifc $1,$$k1\0A.set .Ltrax_rt_${:uid}, 27\0A.endif\0A.ifc $1,$$gp\0A.set .Ltrax_rt_${:uid}, 28\0A.endif\0A.ifc $1,$$sp\0A.set .Ltrax_rt_${:uid}, 29\0A.endif\0A.ifc $1,$$fp\0A.set .Ltrax_rt_${:uid}, 30\0A.endif\0A.ifc $1,$$ra\0A.set .Ltrax_rt_${:uid}, 31\0A.endif\0A.irp r,0,1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17,18,19,20,21,22,23,24,25,26,27,28,29,30,31\0A.ifc $2,$$\\r\0A.set .Ltrax_rd_${:uid}, \\r\0A.endif\0A.endr\0A.ifc $2,$$zero\0A.set .Ltrax_rd_${:uid}, 0\0A.endif\0A.ifc $2,$$at\0A.set .Ltrax_rd_${:uid}, 1\0A.endif\0A.ifc $2,$$v0\0A.set .Ltrax_rd_${:uid}, 2\0A.endif\0A.ifc $2,$$v1\0A.set .Ltrax_rd_${:uid}, 3\0A.endif\0A.ifc $2,$$a0\0A.set .Ltrax_rd_${:uid}, 4\0A.endif\0A.ifc $2,$$a1\0A.set .Ltrax_rd_${:uid}, 5\0A.endif\0A.ifc $2,$$a2\0A.set .Ltrax_rd_${:uid}, 6\0A.endif\0A.ifc $2,$$a3\0A.set .Ltrax_rd_${:uid}, 7\0A.endif\0A.ifc $2,$$t0\0A.set .Ltrax_rd_${:uid}, 8\0A.endif\0A.ifc $2,$$t1\0A.set .Ltrax_rd_${:uid}, 9\0A.endif\0A.ifc $2,$$t2\0A.set .Ltrax_rd_${:uid}, 10\0A.endif\0A.ifc $2,$$t3\0A.set .Ltrax_rd_${:uid}, 11\0A.endif\0A.ifc $2,$$t4\0A.set .Ltrax_rd_${:uid}, 12\0A.endif\0A.ifc $2,$$t5\0A.set .Ltrax_rd_${:uid}, 13\0A.endif\0A.ifc $2,$$t6\0A.set .Ltrax_rd_${:uid}, 14\0A.endif\0A.ifc $2,$$t7\0A.set .Ltrax_rd_${:uid}, 15\0A.endif\0A.ifc $2,$$s0\0A.set .Ltrax_rd_${:uid}, 16\0A.endif\0A.ifc $2,$$s1\0A.set .Ltrax_rd_${:uid}, 17\0A.endif\0A.ifc $2,$$s2\0A.set .Ltrax_rd_${:uid}, 18\0A.endif\0A.ifc $2,$$s3\0A.set .Ltrax_rd_${:uid}, 19\0A.endif\0A.ifc $2,$$s4\0A.set .Ltrax_rd_${:uid}, 20\0A.endif\0A.ifc $2,$$s5\0A.set .Ltrax_rd_${:uid}, 21\0A.endif\0A.ifc $2,$$s6\0A.set .Ltrax_rd_${:uid}, 22\0A.endif\0A.ifc $2,$$s7\0A.set .Ltrax_rd_${:uid}, 23\0A.endif\0A.ifc $2,$$t8\0A.set .Ltrax_rd_${:uid}, 24\0A.endif\0A.ifc $2,$$t9\0A.set .Ltrax_rd_${:uid}, 25\0A.endif\0A.ifc $2,$$k0\0A.set .Ltrax_rd_${:uid}, 26\0A.endif\0A.ifc $2,$$k1\0A.set .Ltrax_rd_${:uid}, 27\0A.endif\0A.ifc $2,$$gp\0A.set .Ltrax_rd_${:uid}, 28\0A.endif\0A.ifc $2,$$sp\0A.set .Ltrax_rd_${:uid}, 29\0A.endif\0A.ifc $2,$$fp\0A.set .Ltrax_rd_${:uid}, 30\0A.endif\0A.ifc $2,$$ra\0A.set .Ltrax_rd_${:uid}, 31\0A.endif\0A.word 0x7000001d | (.Ltrax_rs_${:uid} << 21) | (.Ltrax_rt_${:uid} << 16) | (.Ltrax_rd_${:uid} << 11)\0A.set pop", "r,r,r"(i32 257, i32 %26, i32 16)
  unreachable

check.ok4:                                        ; preds = %check.ok2
  %27 = getelementptr inbounds [4 x float], [4 x float]* %a, i32 0, i32 %21
  %28 = load float, float* %27, align 4
  %29 = fadd float %20, %28
  call void @"trax::store_f32"(i32 0, float %29)
  ret void
}

define internal float @"slices::sum"({ float*, i32 } %0) {
entry:
  %xs = alloca { float*, i32 }, align 8
  store { float*, i32 } %0, { float*, i32 }* %xs, align 4
  %s = alloca float, align 4
  %for.idx = alloca i32, align 4
  %for.item = alloca { i32, float* }, align 8
  %i = alloca i32, align 4
  %x = alloca float*, align 4
  br label %start

start:                                            ; preds = %entry
  store float 0.000000e+00, float* %s, align 4
  %1 = load { float*, i32 }, { float*, i32 }* %xs, align 4
  %ptr = extractvalue { float*, i32 } %1, 0
  %len = extractvalue { float*, i32 } %1, 1
  store i32 0, i32* %for.idx, align 4
  br label %for.cond

for.cond:                                         ; preds = %for.next, %start
  %2 = load i32, i32* %for.idx, align 4
  %3 = icmp ult i32 %2, %len
  br i1 %3, label %for.body, label %for.end

for.body:                                         ; preds = %for.cond
  %4 = getelementptr inbounds float, float* %ptr, i32 %2
  %5 = insertvalue { i32, float* } undef, i32 %2, 0
  %6 = insertvalue { i32, float* } %5, float* %4, 1
  store { i32, float* } %6, { i32, float* }* %for.item, align 4
  %7 = getelementptr inbounds { i32, float* }, { i32, float* }* %for.item, i32 0, i32 0
  %8 = load i32, i32* %7, align 4
  store i32 %8, i32* %i, align 4
  %9 = getelementptr inbounds { i32, float* }, { i32, float* }* %for.item, i32 0, i32 1
  %10 = load float*, float** %9, align 4
  store float* %10, float** %x, align 4
  %11 = load float*, float** %x, align 4
  %12 = load float, float* %11, align 4
  %13 = load i32, i32* %i, align 4
  %14 = uitofp i32 %13 to float
  %15 = fmul float %12, %14
  %16 = load float, float* %s, align 4
  %17 = fadd float %16, %15
  store float %17, float* %s, align 4
  br label %for.next

for.next:                                         ; preds = %for.body
  %18 = load i32, i32* %for.idx, align 4
  %19 = add i32 %18, 1
  store i32 %19, i32* %for.idx, align 4
  br label %for.cond

for.end:                                          ; preds = %for.cond
  %20 = load float, float* %s, align 4
  ret float %20

for.nomatch:                                      ; No predecessors!
  unreachable
}

