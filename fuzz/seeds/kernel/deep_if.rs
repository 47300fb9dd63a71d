// 3000 nested `if`s (once overflowed the compiler's stack).
fn trax_main() {
    let x = trax::global_id();
if x < 1 {
if x < 2 {
if x < 3 {
if x < 4 {
if x < 5 {
if x < 6 {
if x < 7 {
if x < 8 {
if x < 9 {
if x < 10 {
if x < 11 {
if x < 12 {
if x < 13 {
if x < 14 {
if x < 15 {
if x < 16 {
if x < 17 {
if x < 18 {
if x < 19 {
if x < 20 {
if x < 21 {
if x < 22 {
if x < 23 {
if x < 24 {
if x < 25 {
if x < 26 {
if x < 27 {
if x < 28 {
if x < 29 {
if x < 30 {
if x < 31 {
if x < 32 {
if x < 33 {
if x < 34 {
if x < 35 {
if x < 36 {
if x < 37 {
if x < 38 {
if x < 39 {
if x < 40 {
if x < 41 {
if x < 42 {
if x < 43 {
if x < 44 {
if x < 45 {
if x < 46 {
if x < 47 {
if x < 48 {
if x < 49 {
if x < 50 {
if x < 51 {
if x < 52 {
if x < 53 {
if x < 54 {
if x < 55 {
if x < 56 {
if x < 57 {
if x < 58 {
if x < 59 {
if x < 60 {
if x < 61 {
if x < 62 {
if x < 63 {
if x < 64 {
if x < 65 {
if x < 66 {
if x < 67 {
if x < 68 {
if x < 69 {
if x < 70 {
if x < 71 {
if x < 72 {
if x < 73 {
if x < 74 {
if x < 75 {
if x < 76 {
if x < 77 {
if x < 78 {
if x < 79 {
if x < 80 {
if x < 81 {
if x < 82 {
if x < 83 {
if x < 84 {
if x < 85 {
if x < 86 {
if x < 87 {
if x < 88 {
if x < 89 {
if x < 90 {
if x < 91 {
if x < 92 {
if x < 93 {
if x < 94 {
if x < 95 {
if x < 96 {
if x < 97 {
if x < 98 {
if x < 99 {
if x < 100 {
if x < 101 {
if x < 102 {
if x < 103 {
if x < 104 {
if x < 105 {
if x < 106 {
if x < 107 {
if x < 108 {
if x < 109 {
if x < 110 {
if x < 111 {
if x < 112 {
if x < 113 {
if x < 114 {
if x < 115 {
if x < 116 {
if x < 117 {
if x < 118 {
if x < 119 {
if x < 120 {
if x < 121 {
if x < 122 {
if x < 123 {
if x < 124 {
if x < 125 {
if x < 126 {
if x < 127 {
if x < 128 {
if x < 129 {
if x < 130 {
if x < 131 {
if x < 132 {
if x < 133 {
if x < 134 {
if x < 135 {
if x < 136 {
if x < 137 {
if x < 138 {
if x < 139 {
if x < 140 {
if x < 141 {
if x < 142 {
if x < 143 {
if x < 144 {
if x < 145 {
if x < 146 {
if x < 147 {
if x < 148 {
if x < 149 {
if x < 150 {
if x < 151 {
if x < 152 {
if x < 153 {
if x < 154 {
if x < 155 {
if x < 156 {
if x < 157 {
if x < 158 {
if x < 159 {
if x < 160 {
if x < 161 {
if x < 162 {
if x < 163 {
if x < 164 {
if x < 165 {
if x < 166 {
if x < 167 {
if x < 168 {
if x < 169 {
if x < 170 {
if x < 171 {
if x < 172 {
if x < 173 {
if x < 174 {
if x < 175 {
if x < 176 {
if x < 177 {
if x < 178 {
if x < 179 {
if x < 180 {
if x < 181 {
if x < 182 {
if x < 183 {
if x < 184 {
if x < 185 {
if x < 186 {
if x < 187 {
if x < 188 {
if x < 189 {
if x < 190 {
if x < 191 {
if x < 192 {
if x < 193 {
if x < 194 {
if x < 195 {
if x < 196 {
if x < 197 {
if x < 198 {
if x < 199 {
if x < 200 {
if x < 201 {
if x < 202 {
if x < 203 {
if x < 204 {
if x < 205 {
if x < 206 {
if x < 207 {
if x < 208 {
if x < 209 {
if x < 210 {
if x < 211 {
if x < 212 {
if x < 213 {
if x < 214 {
if x < 215 {
if x < 216 {
if x < 217 {
if x < 218 {
if x < 219 {
if x < 220 {
if x < 221 {
if x < 222 {
if x < 223 {
if x < 224 {
if x < 225 {
if x < 226 {
if x < 227 {
if x < 228 {
if x < 229 {
if x < 230 {
if x < 231 {
if x < 232 {
if x < 233 {
if x < 234 {
if x < 235 {
if x < 236 {
if x < 237 {
if x < 238 {
if x < 239 {
if x < 240 {
if x < 241 {
if x < 242 {
if x < 243 {
if x < 244 {
if x < 245 {
if x < 246 {
if x < 247 {
if x < 248 {
if x < 249 {
if x < 250 {
if x < 251 {
if x < 252 {
if x < 253 {
if x < 254 {
if x < 255 {
if x < 256 {
if x < 257 {
if x < 258 {
if x < 259 {
if x < 260 {
if x < 261 {
if x < 262 {
if x < 263 {
if x < 264 {
if x < 265 {
if x < 266 {
if x < 267 {
if x < 268 {
if x < 269 {
if x < 270 {
if x < 271 {
if x < 272 {
if x < 273 {
if x < 274 {
if x < 275 {
if x < 276 {
if x < 277 {
if x < 278 {
if x < 279 {
if x < 280 {
if x < 281 {
if x < 282 {
if x < 283 {
if x < 284 {
if x < 285 {
if x < 286 {
if x < 287 {
if x < 288 {
if x < 289 {
if x < 290 {
if x < 291 {
if x < 292 {
if x < 293 {
if x < 294 {
if x < 295 {
if x < 296 {
if x < 297 {
if x < 298 {
if x < 299 {
if x < 300 {
if x < 301 {
if x < 302 {
if x < 303 {
if x < 304 {
if x < 305 {
if x < 306 {
if x < 307 {
if x < 308 {
if x < 309 {
if x < 310 {
if x < 311 {
if x < 312 {
if x < 313 {
if x < 314 {
if x < 315 {
if x < 316 {
if x < 317 {
if x < 318 {
if x < 319 {
if x < 320 {
if x < 321 {
if x < 322 {
if x < 323 {
if x < 324 {
if x < 325 {
if x < 326 {
if x < 327 {
if x < 328 {
if x < 329 {
if x < 330 {
if x < 331 {
if x < 332 {
if x < 333 {
if x < 334 {
if x < 335 {
if x < 336 {
if x < 337 {
if x < 338 {
if x < 339 {
if x < 340 {
if x < 341 {
if x < 342 {
if x < 343 {
if x < 344 {
if x < 345 {
if x < 346 {
if x < 347 {
if x < 348 {
if x < 349 {
if x < 350 {
if x < 351 {
if x < 352 {
if x < 353 {
if x < 354 {
if x < 355 {
if x < 356 {
if x < 357 {
if x < 358 {
if x < 359 {
if x < 360 {
if x < 361 {
if x < 362 {
if x < 363 {
if x < 364 {
if x < 365 {
if x < 366 {
if x < 367 {
if x < 368 {
if x < 369 {
if x < 370 {
if x < 371 {
if x < 372 {
if x < 373 {
if x < 374 {
if x < 375 {
if x < 376 {
if x < 377 {
if x < 378 {
if x < 379 {
if x < 380 {
if x < 381 {
if x < 382 {
if x < 383 {
if x < 384 {
if x < 385 {
if x < 386 {
if x < 387 {
if x < 388 {
if x < 389 {
if x < 390 {
if x < 391 {
if x < 392 {
if x < 393 {
if x < 394 {
if x < 395 {
if x < 396 {
if x < 397 {
if x < 398 {
if x < 399 {
if x < 400 {
if x < 401 {
if x < 402 {
if x < 403 {
if x < 404 {
if x < 405 {
if x < 406 {
if x < 407 {
if x < 408 {
if x < 409 {
if x < 410 {
if x < 411 {
if x < 412 {
if x < 413 {
if x < 414 {
if x < 415 {
if x < 416 {
if x < 417 {
if x < 418 {
if x < 419 {
if x < 420 {
if x < 421 {
if x < 422 {
if x < 423 {
if x < 424 {
if x < 425 {
if x < 426 {
if x < 427 {
if x < 428 {
if x < 429 {
if x < 430 {
if x < 431 {
if x < 432 {
if x < 433 {
if x < 434 {
if x < 435 {
if x < 436 {
if x < 437 {
if x < 438 {
if x < 439 {
if x < 440 {
if x < 441 {
if x < 442 {
if x < 443 {
if x < 444 {
if x < 445 {
if x < 446 {
if x < 447 {
if x < 448 {
if x < 449 {
if x < 450 {
if x < 451 {
if x < 452 {
if x < 453 {
if x < 454 {
if x < 455 {
if x < 456 {
if x < 457 {
if x < 458 {
if x < 459 {
if x < 460 {
if x < 461 {
if x < 462 {
if x < 463 {
if x < 464 {
if x < 465 {
if x < 466 {
if x < 467 {
if x < 468 {
if x < 469 {
if x < 470 {
if x < 471 {
if x < 472 {
if x < 473 {
if x < 474 {
if x < 475 {
if x < 476 {
if x < 477 {
if x < 478 {
if x < 479 {
if x < 480 {
if x < 481 {
if x < 482 {
if x < 483 {
if x < 484 {
if x < 485 {
if x < 486 {
if x < 487 {
if x < 488 {
if x < 489 {
if x < 490 {
if x < 491 {
if x < 492 {
if x < 493 {
if x < 494 {
if x < 495 {
if x < 496 {
if x < 497 {
if x < 498 {
if x < 499 {
if x < 500 {
if x < 501 {
if x < 502 {
if x < 503 {
if x < 504 {
if x < 505 {
if x < 506 {
if x < 507 {
if x < 508 {
if x < 509 {
if x < 510 {
if x < 511 {
if x < 512 {
if x < 513 {
if x < 514 {
if x < 515 {
if x < 516 {
if x < 517 {
if x < 518 {
if x < 519 {
if x < 520 {
if x < 521 {
if x < 522 {
if x < 523 {
if x < 524 {
if x < 525 {
if x < 526 {
if x < 527 {
if x < 528 {
if x < 529 {
if x < 530 {
if x < 531 {
if x < 532 {
if x < 533 {
if x < 534 {
if x < 535 {
if x < 536 {
if x < 537 {
if x < 538 {
if x < 539 {
if x < 540 {
if x < 541 {
if x < 542 {
if x < 543 {
if x < 544 {
if x < 545 {
if x < 546 {
if x < 547 {
if x < 548 {
if x < 549 {
if x < 550 {
if x < 551 {
if x < 552 {
if x < 553 {
if x < 554 {
if x < 555 {
if x < 556 {
if x < 557 {
if x < 558 {
if x < 559 {
if x < 560 {
if x < 561 {
if x < 562 {
if x < 563 {
if x < 564 {
if x < 565 {
if x < 566 {
if x < 567 {
if x < 568 {
if x < 569 {
if x < 570 {
if x < 571 {
if x < 572 {
if x < 573 {
if x < 574 {
if x < 575 {
if x < 576 {
if x < 577 {
if x < 578 {
if x < 579 {
if x < 580 {
if x < 581 {
if x < 582 {
if x < 583 {
if x < 584 {
if x < 585 {
if x < 586 {
if x < 587 {
if x < 588 {
if x < 589 {
if x < 590 {
if x < 591 {
if x < 592 {
if x < 593 {
if x < 594 {
if x < 595 {
if x < 596 {
if x < 597 {
if x < 598 {
if x < 599 {
if x < 600 {
if x < 601 {
if x < 602 {
if x < 603 {
if x < 604 {
if x < 605 {
if x < 606 {
if x < 607 {
if x < 608 {
if x < 609 {
if x < 610 {
if x < 611 {
if x < 612 {
if x < 613 {
if x < 614 {
if x < 615 {
if x < 616 {
if x < 617 {
if x < 618 {
if x < 619 {
if x < 620 {
if x < 621 {
if x < 622 {
if x < 623 {
if x < 624 {
if x < 625 {
if x < 626 {
if x < 627 {
if x < 628 {
if x < 629 {
if x < 630 {
if x < 631 {
if x < 632 {
if x < 633 {
if x < 634 {
if x < 635 {
if x < 636 {
if x < 637 {
if x < 638 {
if x < 639 {
if x < 640 {
if x < 641 {
if x < 642 {
if x < 643 {
if x < 644 {
if x < 645 {
if x < 646 {
if x < 647 {
if x < 648 {
if x < 649 {
if x < 650 {
if x < 651 {
if x < 652 {
if x < 653 {
if x < 654 {
if x < 655 {
if x < 656 {
if x < 657 {
if x < 658 {
if x < 659 {
if x < 660 {
if x < 661 {
if x < 662 {
if x < 663 {
if x < 664 {
if x < 665 {
if x < 666 {
if x < 667 {
if x < 668 {
if x < 669 {
if x < 670 {
if x < 671 {
if x < 672 {
if x < 673 {
if x < 674 {
if x < 675 {
if x < 676 {
if x < 677 {
if x < 678 {
if x < 679 {
if x < 680 {
if x < 681 {
if x < 682 {
if x < 683 {
if x < 684 {
if x < 685 {
if x < 686 {
if x < 687 {
if x < 688 {
if x < 689 {
if x < 690 {
if x < 691 {
if x < 692 {
if x < 693 {
if x < 694 {
if x < 695 {
if x < 696 {
if x < 697 {
if x < 698 {
if x < 699 {
if x < 700 {
if x < 701 {
if x < 702 {
if x < 703 {
if x < 704 {
if x < 705 {
if x < 706 {
if x < 707 {
if x < 708 {
if x < 709 {
if x < 710 {
if x < 711 {
if x < 712 {
if x < 713 {
if x < 714 {
if x < 715 {
if x < 716 {
if x < 717 {
if x < 718 {
if x < 719 {
if x < 720 {
if x < 721 {
if x < 722 {
if x < 723 {
if x < 724 {
if x < 725 {
if x < 726 {
if x < 727 {
if x < 728 {
if x < 729 {
if x < 730 {
if x < 731 {
if x < 732 {
if x < 733 {
if x < 734 {
if x < 735 {
if x < 736 {
if x < 737 {
if x < 738 {
if x < 739 {
if x < 740 {
if x < 741 {
if x < 742 {
if x < 743 {
if x < 744 {
if x < 745 {
if x < 746 {
if x < 747 {
if x < 748 {
if x < 749 {
if x < 750 {
if x < 751 {
if x < 752 {
if x < 753 {
if x < 754 {
if x < 755 {
if x < 756 {
if x < 757 {
if x < 758 {
if x < 759 {
if x < 760 {
if x < 761 {
if x < 762 {
if x < 763 {
if x < 764 {
if x < 765 {
if x < 766 {
if x < 767 {
if x < 768 {
if x < 769 {
if x < 770 {
if x < 771 {
if x < 772 {
if x < 773 {
if x < 774 {
if x < 775 {
if x < 776 {
if x < 777 {
if x < 778 {
if x < 779 {
if x < 780 {
if x < 781 {
if x < 782 {
if x < 783 {
if x < 784 {
if x < 785 {
if x < 786 {
if x < 787 {
if x < 788 {
if x < 789 {
if x < 790 {
if x < 791 {
if x < 792 {
if x < 793 {
if x < 794 {
if x < 795 {
if x < 796 {
if x < 797 {
if x < 798 {
if x < 799 {
if x < 800 {
if x < 801 {
if x < 802 {
if x < 803 {
if x < 804 {
if x < 805 {
if x < 806 {
if x < 807 {
if x < 808 {
if x < 809 {
if x < 810 {
if x < 811 {
if x < 812 {
if x < 813 {
if x < 814 {
if x < 815 {
if x < 816 {
if x < 817 {
if x < 818 {
if x < 819 {
if x < 820 {
if x < 821 {
if x < 822 {
if x < 823 {
if x < 824 {
if x < 825 {
if x < 826 {
if x < 827 {
if x < 828 {
if x < 829 {
if x < 830 {
if x < 831 {
if x < 832 {
if x < 833 {
if x < 834 {
if x < 835 {
if x < 836 {
if x < 837 {
if x < 838 {
if x < 839 {
if x < 840 {
if x < 841 {
if x < 842 {
if x < 843 {
if x < 844 {
if x < 845 {
if x < 846 {
if x < 847 {
if x < 848 {
if x < 849 {
if x < 850 {
if x < 851 {
if x < 852 {
if x < 853 {
if x < 854 {
if x < 855 {
if x < 856 {
if x < 857 {
if x < 858 {
if x < 859 {
if x < 860 {
if x < 861 {
if x < 862 {
if x < 863 {
if x < 864 {
if x < 865 {
if x < 866 {
if x < 867 {
if x < 868 {
if x < 869 {
if x < 870 {
if x < 871 {
if x < 872 {
if x < 873 {
if x < 874 {
if x < 875 {
if x < 876 {
if x < 877 {
if x < 878 {
if x < 879 {
if x < 880 {
if x < 881 {
if x < 882 {
if x < 883 {
if x < 884 {
if x < 885 {
if x < 886 {
if x < 887 {
if x < 888 {
if x < 889 {
if x < 890 {
if x < 891 {
if x < 892 {
if x < 893 {
if x < 894 {
if x < 895 {
if x < 896 {
if x < 897 {
if x < 898 {
if x < 899 {
if x < 900 {
if x < 901 {
if x < 902 {
if x < 903 {
if x < 904 {
if x < 905 {
if x < 906 {
if x < 907 {
if x < 908 {
if x < 909 {
if x < 910 {
if x < 911 {
if x < 912 {
if x < 913 {
if x < 914 {
if x < 915 {
if x < 916 {
if x < 917 {
if x < 918 {
if x < 919 {
if x < 920 {
if x < 921 {
if x < 922 {
if x < 923 {
if x < 924 {
if x < 925 {
if x < 926 {
if x < 927 {
if x < 928 {
if x < 929 {
if x < 930 {
if x < 931 {
if x < 932 {
if x < 933 {
if x < 934 {
if x < 935 {
if x < 936 {
if x < 937 {
if x < 938 {
if x < 939 {
if x < 940 {
if x < 941 {
if x < 942 {
if x < 943 {
if x < 944 {
if x < 945 {
if x < 946 {
if x < 947 {
if x < 948 {
if x < 949 {
if x < 950 {
if x < 951 {
if x < 952 {
if x < 953 {
if x < 954 {
if x < 955 {
if x < 956 {
if x < 957 {
if x < 958 {
if x < 959 {
if x < 960 {
if x < 961 {
if x < 962 {
if x < 963 {
if x < 964 {
if x < 965 {
if x < 966 {
if x < 967 {
if x < 968 {
if x < 969 {
if x < 970 {
if x < 971 {
if x < 972 {
if x < 973 {
if x < 974 {
if x < 975 {
if x < 976 {
if x < 977 {
if x < 978 {
if x < 979 {
if x < 980 {
if x < 981 {
if x < 982 {
if x < 983 {
if x < 984 {
if x < 985 {
if x < 986 {
if x < 987 {
if x < 988 {
if x < 989 {
if x < 990 {
if x < 991 {
if x < 992 {
if x < 993 {
if x < 994 {
if x < 995 {
if x < 996 {
if x < 997 {
if x < 998 {
if x < 999 {
if x < 1000 {
if x < 1001 {
if x < 1002 {
if x < 1003 {
if x < 1004 {
if x < 1005 {
if x < 1006 {
if x < 1007 {
if x < 1008 {
if x < 1009 {
if x < 1010 {
if x < 1011 {
if x < 1012 {
if x < 1013 {
if x < 1014 {
if x < 1015 {
if x < 1016 {
if x < 1017 {
if x < 1018 {
if x < 1019 {
if x < 1020 {
if x < 1021 {
if x < 1022 {
if x < 1023 {
if x < 1024 {
if x < 1025 {
if x < 1026 {
if x < 1027 {
if x < 1028 {
if x < 1029 {
if x < 1030 {
if x < 1031 {
if x < 1032 {
if x < 1033 {
if x < 1034 {
if x < 1035 {
if x < 1036 {
if x < 1037 {
if x < 1038 {
if x < 1039 {
if x < 1040 {
if x < 1041 {
if x < 1042 {
if x < 1043 {
if x < 1044 {
if x < 1045 {
if x < 1046 {
if x < 1047 {
if x < 1048 {
if x < 1049 {
if x < 1050 {
if x < 1051 {
if x < 1052 {
if x < 1053 {
if x < 1054 {
if x < 1055 {
if x < 1056 {
if x < 1057 {
if x < 1058 {
if x < 1059 {
if x < 1060 {
if x < 1061 {
if x < 1062 {
if x < 1063 {
if x < 1064 {
if x < 1065 {
if x < 1066 {
if x < 1067 {
if x < 1068 {
if x < 1069 {
if x < 1070 {
if x < 1071 {
if x < 1072 {
if x < 1073 {
if x < 1074 {
if x < 1075 {
if x < 1076 {
if x < 1077 {
if x < 1078 {
if x < 1079 {
if x < 1080 {
if x < 1081 {
if x < 1082 {
if x < 1083 {
if x < 1084 {
if x < 1085 {
if x < 1086 {
if x < 1087 {
if x < 1088 {
if x < 1089 {
if x < 1090 {
if x < 1091 {
if x < 1092 {
if x < 1093 {
if x < 1094 {
if x < 1095 {
if x < 1096 {
if x < 1097 {
if x < 1098 {
if x < 1099 {
if x < 1100 {
if x < 1101 {
if x < 1102 {
if x < 1103 {
if x < 1104 {
if x < 1105 {
if x < 1106 {
if x < 1107 {
if x < 1108 {
if x < 1109 {
if x < 1110 {
if x < 1111 {
if x < 1112 {
if x < 1113 {
if x < 1114 {
if x < 1115 {
if x < 1116 {
if x < 1117 {
if x < 1118 {
if x < 1119 {
if x < 1120 {
if x < 1121 {
if x < 1122 {
if x < 1123 {
if x < 1124 {
if x < 1125 {
if x < 1126 {
if x < 1127 {
if x < 1128 {
if x < 1129 {
if x < 1130 {
if x < 1131 {
if x < 1132 {
if x < 1133 {
if x < 1134 {
if x < 1135 {
if x < 1136 {
if x < 1137 {
if x < 1138 {
if x < 1139 {
if x < 1140 {
if x < 1141 {
if x < 1142 {
if x < 1143 {
if x < 1144 {
if x < 1145 {
if x < 1146 {
if x < 1147 {
if x < 1148 {
if x < 1149 {
if x < 1150 {
if x < 1151 {
if x < 1152 {
if x < 1153 {
if x < 1154 {
if x < 1155 {
if x < 1156 {
if x < 1157 {
if x < 1158 {
if x < 1159 {
if x < 1160 {
if x < 1161 {
if x < 1162 {
if x < 1163 {
if x < 1164 {
if x < 1165 {
if x < 1166 {
if x < 1167 {
if x < 1168 {
if x < 1169 {
if x < 1170 {
if x < 1171 {
if x < 1172 {
if x < 1173 {
if x < 1174 {
if x < 1175 {
if x < 1176 {
if x < 1177 {
if x < 1178 {
if x < 1179 {
if x < 1180 {
if x < 1181 {
if x < 1182 {
if x < 1183 {
if x < 1184 {
if x < 1185 {
if x < 1186 {
if x < 1187 {
if x < 1188 {
if x < 1189 {
if x < 1190 {
if x < 1191 {
if x < 1192 {
if x < 1193 {
if x < 1194 {
if x < 1195 {
if x < 1196 {
if x < 1197 {
if x < 1198 {
if x < 1199 {
if x < 1200 {
if x < 1201 {
if x < 1202 {
if x < 1203 {
if x < 1204 {
if x < 1205 {
if x < 1206 {
if x < 1207 {
if x < 1208 {
if x < 1209 {
if x < 1210 {
if x < 1211 {
if x < 1212 {
if x < 1213 {
if x < 1214 {
if x < 1215 {
if x < 1216 {
if x < 1217 {
if x < 1218 {
if x < 1219 {
if x < 1220 {
if x < 1221 {
if x < 1222 {
if x < 1223 {
if x < 1224 {
if x < 1225 {
if x < 1226 {
if x < 1227 {
if x < 1228 {
if x < 1229 {
if x < 1230 {
if x < 1231 {
if x < 1232 {
if x < 1233 {
if x < 1234 {
if x < 1235 {
if x < 1236 {
if x < 1237 {
if x < 1238 {
if x < 1239 {
if x < 1240 {
if x < 1241 {
if x < 1242 {
if x < 1243 {
if x < 1244 {
if x < 1245 {
if x < 1246 {
if x < 1247 {
if x < 1248 {
if x < 1249 {
if x < 1250 {
if x < 1251 {
if x < 1252 {
if x < 1253 {
if x < 1254 {
if x < 1255 {
if x < 1256 {
if x < 1257 {
if x < 1258 {
if x < 1259 {
if x < 1260 {
if x < 1261 {
if x < 1262 {
if x < 1263 {
if x < 1264 {
if x < 1265 {
if x < 1266 {
if x < 1267 {
if x < 1268 {
if x < 1269 {
if x < 1270 {
if x < 1271 {
if x < 1272 {
if x < 1273 {
if x < 1274 {
if x < 1275 {
if x < 1276 {
if x < 1277 {
if x < 1278 {
if x < 1279 {
if x < 1280 {
if x < 1281 {
if x < 1282 {
if x < 1283 {
if x < 1284 {
if x < 1285 {
if x < 1286 {
if x < 1287 {
if x < 1288 {
if x < 1289 {
if x < 1290 {
if x < 1291 {
if x < 1292 {
if x < 1293 {
if x < 1294 {
if x < 1295 {
if x < 1296 {
if x < 1297 {
if x < 1298 {
if x < 1299 {
if x < 1300 {
if x < 1301 {
if x < 1302 {
if x < 1303 {
if x < 1304 {
if x < 1305 {
if x < 1306 {
if x < 1307 {
if x < 1308 {
if x < 1309 {
if x < 1310 {
if x < 1311 {
if x < 1312 {
if x < 1313 {
if x < 1314 {
if x < 1315 {
if x < 1316 {
if x < 1317 {
if x < 1318 {
if x < 1319 {
if x < 1320 {
if x < 1321 {
if x < 1322 {
if x < 1323 {
if x < 1324 {
if x < 1325 {
if x < 1326 {
if x < 1327 {
if x < 1328 {
if x < 1329 {
if x < 1330 {
if x < 1331 {
if x < 1332 {
if x < 1333 {
if x < 1334 {
if x < 1335 {
if x < 1336 {
if x < 1337 {
if x < 1338 {
if x < 1339 {
if x < 1340 {
if x < 1341 {
if x < 1342 {
if x < 1343 {
if x < 1344 {
if x < 1345 {
if x < 1346 {
if x < 1347 {
if x < 1348 {
if x < 1349 {
if x < 1350 {
if x < 1351 {
if x < 1352 {
if x < 1353 {
if x < 1354 {
if x < 1355 {
if x < 1356 {
if x < 1357 {
if x < 1358 {
if x < 1359 {
if x < 1360 {
if x < 1361 {
if x < 1362 {
if x < 1363 {
if x < 1364 {
if x < 1365 {
if x < 1366 {
if x < 1367 {
if x < 1368 {
if x < 1369 {
if x < 1370 {
if x < 1371 {
if x < 1372 {
if x < 1373 {
if x < 1374 {
if x < 1375 {
if x < 1376 {
if x < 1377 {
if x < 1378 {
if x < 1379 {
if x < 1380 {
if x < 1381 {
if x < 1382 {
if x < 1383 {
if x < 1384 {
if x < 1385 {
if x < 1386 {
if x < 1387 {
if x < 1388 {
if x < 1389 {
if x < 1390 {
if x < 1391 {
if x < 1392 {
if x < 1393 {
if x < 1394 {
if x < 1395 {
if x < 1396 {
if x < 1397 {
if x < 1398 {
if x < 1399 {
if x < 1400 {
if x < 1401 {
if x < 1402 {
if x < 1403 {
if x < 1404 {
if x < 1405 {
if x < 1406 {
if x < 1407 {
if x < 1408 {
if x < 1409 {
if x < 1410 {
if x < 1411 {
if x < 1412 {
if x < 1413 {
if x < 1414 {
if x < 1415 {
if x < 1416 {
if x < 1417 {
if x < 1418 {
if x < 1419 {
if x < 1420 {
if x < 1421 {
if x < 1422 {
if x < 1423 {
if x < 1424 {
if x < 1425 {
if x < 1426 {
if x < 1427 {
if x < 1428 {
if x < 1429 {
if x < 1430 {
if x < 1431 {
if x < 1432 {
if x < 1433 {
if x < 1434 {
if x < 1435 {
if x < 1436 {
if x < 1437 {
if x < 1438 {
if x < 1439 {
if x < 1440 {
if x < 1441 {
if x < 1442 {
if x < 1443 {
if x < 1444 {
if x < 1445 {
if x < 1446 {
if x < 1447 {
if x < 1448 {
if x < 1449 {
if x < 1450 {
if x < 1451 {
if x < 1452 {
if x < 1453 {
if x < 1454 {
if x < 1455 {
if x < 1456 {
if x < 1457 {
if x < 1458 {
if x < 1459 {
if x < 1460 {
if x < 1461 {
if x < 1462 {
if x < 1463 {
if x < 1464 {
if x < 1465 {
if x < 1466 {
if x < 1467 {
if x < 1468 {
if x < 1469 {
if x < 1470 {
if x < 1471 {
if x < 1472 {
if x < 1473 {
if x < 1474 {
if x < 1475 {
if x < 1476 {
if x < 1477 {
if x < 1478 {
if x < 1479 {
if x < 1480 {
if x < 1481 {
if x < 1482 {
if x < 1483 {
if x < 1484 {
if x < 1485 {
if x < 1486 {
if x < 1487 {
if x < 1488 {
if x < 1489 {
if x < 1490 {
if x < 1491 {
if x < 1492 {
if x < 1493 {
if x < 1494 {
if x < 1495 {
if x < 1496 {
if x < 1497 {
if x < 1498 {
if x < 1499 {
if x < 1500 {
if x < 1501 {
if x < 1502 {
if x < 1503 {
if x < 1504 {
if x < 1505 {
if x < 1506 {
if x < 1507 {
if x < 1508 {
if x < 1509 {
if x < 1510 {
if x < 1511 {
if x < 1512 {
if x < 1513 {
if x < 1514 {
if x < 1515 {
if x < 1516 {
if x < 1517 {
if x < 1518 {
if x < 1519 {
if x < 1520 {
if x < 1521 {
if x < 1522 {
if x < 1523 {
if x < 1524 {
if x < 1525 {
if x < 1526 {
if x < 1527 {
if x < 1528 {
if x < 1529 {
if x < 1530 {
if x < 1531 {
if x < 1532 {
if x < 1533 {
if x < 1534 {
if x < 1535 {
if x < 1536 {
if x < 1537 {
if x < 1538 {
if x < 1539 {
if x < 1540 {
if x < 1541 {
if x < 1542 {
if x < 1543 {
if x < 1544 {
if x < 1545 {
if x < 1546 {
if x < 1547 {
if x < 1548 {
if x < 1549 {
if x < 1550 {
if x < 1551 {
if x < 1552 {
if x < 1553 {
if x < 1554 {
if x < 1555 {
if x < 1556 {
if x < 1557 {
if x < 1558 {
if x < 1559 {
if x < 1560 {
if x < 1561 {
if x < 1562 {
if x < 1563 {
if x < 1564 {
if x < 1565 {
if x < 1566 {
if x < 1567 {
if x < 1568 {
if x < 1569 {
if x < 1570 {
if x < 1571 {
if x < 1572 {
if x < 1573 {
if x < 1574 {
if x < 1575 {
if x < 1576 {
if x < 1577 {
if x < 1578 {
if x < 1579 {
if x < 1580 {
if x < 1581 {
if x < 1582 {
if x < 1583 {
if x < 1584 {
if x < 1585 {
if x < 1586 {
if x < 1587 {
if x < 1588 {
if x < 1589 {
if x < 1590 {
if x < 1591 {
if x < 1592 {
if x < 1593 {
if x < 1594 {
if x < 1595 {
if x < 1596 {
if x < 1597 {
if x < 1598 {
if x < 1599 {
if x < 1600 {
if x < 1601 {
if x < 1602 {
if x < 1603 {
if x < 1604 {
if x < 1605 {
if x < 1606 {
if x < 1607 {
if x < 1608 {
if x < 1609 {
if x < 1610 {
if x < 1611 {
if x < 1612 {
if x < 1613 {
if x < 1614 {
if x < 1615 {
if x < 1616 {
if x < 1617 {
if x < 1618 {
if x < 1619 {
if x < 1620 {
if x < 1621 {
if x < 1622 {
if x < 1623 {
if x < 1624 {
if x < 1625 {
if x < 1626 {
if x < 1627 {
if x < 1628 {
if x < 1629 {
if x < 1630 {
if x < 1631 {
if x < 1632 {
if x < 1633 {
if x < 1634 {
if x < 1635 {
if x < 1636 {
if x < 1637 {
if x < 1638 {
if x < 1639 {
if x < 1640 {
if x < 1641 {
if x < 1642 {
if x < 1643 {
if x < 1644 {
if x < 1645 {
if x < 1646 {
if x < 1647 {
if x < 1648 {
if x < 1649 {
if x < 1650 {
if x < 1651 {
if x < 1652 {
if x < 1653 {
if x < 1654 {
if x < 1655 {
if x < 1656 {
if x < 1657 {
if x < 1658 {
if x < 1659 {
if x < 1660 {
if x < 1661 {
if x < 1662 {
if x < 1663 {
if x < 1664 {
if x < 1665 {
if x < 1666 {
if x < 1667 {
if x < 1668 {
if x < 1669 {
if x < 1670 {
if x < 1671 {
if x < 1672 {
if x < 1673 {
if x < 1674 {
if x < 1675 {
if x < 1676 {
if x < 1677 {
if x < 1678 {
if x < 1679 {
if x < 1680 {
if x < 1681 {
if x < 1682 {
if x < 1683 {
if x < 1684 {
if x < 1685 {
if x < 1686 {
if x < 1687 {
if x < 1688 {
if x < 1689 {
if x < 1690 {
if x < 1691 {
if x < 1692 {
if x < 1693 {
if x < 1694 {
if x < 1695 {
if x < 1696 {
if x < 1697 {
if x < 1698 {
if x < 1699 {
if x < 1700 {
if x < 1701 {
if x < 1702 {
if x < 1703 {
if x < 1704 {
if x < 1705 {
if x < 1706 {
if x < 1707 {
if x < 1708 {
if x < 1709 {
if x < 1710 {
if x < 1711 {
if x < 1712 {
if x < 1713 {
if x < 1714 {
if x < 1715 {
if x < 1716 {
if x < 1717 {
if x < 1718 {
if x < 1719 {
if x < 1720 {
if x < 1721 {
if x < 1722 {
if x < 1723 {
if x < 1724 {
if x < 1725 {
if x < 1726 {
if x < 1727 {
if x < 1728 {
if x < 1729 {
if x < 1730 {
if x < 1731 {
if x < 1732 {
if x < 1733 {
if x < 1734 {
if x < 1735 {
if x < 1736 {
if x < 1737 {
if x < 1738 {
if x < 1739 {
if x < 1740 {
if x < 1741 {
if x < 1742 {
if x < 1743 {
if x < 1744 {
if x < 1745 {
if x < 1746 {
if x < 1747 {
if x < 1748 {
if x < 1749 {
if x < 1750 {
if x < 1751 {
if x < 1752 {
if x < 1753 {
if x < 1754 {
if x < 1755 {
if x < 1756 {
if x < 1757 {
if x < 1758 {
if x < 1759 {
if x < 1760 {
if x < 1761 {
if x < 1762 {
if x < 1763 {
if x < 1764 {
if x < 1765 {
if x < 1766 {
if x < 1767 {
if x < 1768 {
if x < 1769 {
if x < 1770 {
if x < 1771 {
if x < 1772 {
if x < 1773 {
if x < 1774 {
if x < 1775 {
if x < 1776 {
if x < 1777 {
if x < 1778 {
if x < 1779 {
if x < 1780 {
if x < 1781 {
if x < 1782 {
if x < 1783 {
if x < 1784 {
if x < 1785 {
if x < 1786 {
if x < 1787 {
if x < 1788 {
if x < 1789 {
if x < 1790 {
if x < 1791 {
if x < 1792 {
if x < 1793 {
if x < 1794 {
if x < 1795 {
if x < 1796 {
if x < 1797 {
if x < 1798 {
if x < 1799 {
if x < 1800 {
if x < 1801 {
if x < 1802 {
if x < 1803 {
if x < 1804 {
if x < 1805 {
if x < 1806 {
if x < 1807 {
if x < 1808 {
if x < 1809 {
if x < 1810 {
if x < 1811 {
if x < 1812 {
if x < 1813 {
if x < 1814 {
if x < 1815 {
if x < 1816 {
if x < 1817 {
if x < 1818 {
if x < 1819 {
if x < 1820 {
if x < 1821 {
if x < 1822 {
if x < 1823 {
if x < 1824 {
if x < 1825 {
if x < 1826 {
if x < 1827 {
if x < 1828 {
if x < 1829 {
if x < 1830 {
if x < 1831 {
if x < 1832 {
if x < 1833 {
if x < 1834 {
if x < 1835 {
if x < 1836 {
if x < 1837 {
if x < 1838 {
if x < 1839 {
if x < 1840 {
if x < 1841 {
if x < 1842 {
if x < 1843 {
if x < 1844 {
if x < 1845 {
if x < 1846 {
if x < 1847 {
if x < 1848 {
if x < 1849 {
if x < 1850 {
if x < 1851 {
if x < 1852 {
if x < 1853 {
if x < 1854 {
if x < 1855 {
if x < 1856 {
if x < 1857 {
if x < 1858 {
if x < 1859 {
if x < 1860 {
if x < 1861 {
if x < 1862 {
if x < 1863 {
if x < 1864 {
if x < 1865 {
if x < 1866 {
if x < 1867 {
if x < 1868 {
if x < 1869 {
if x < 1870 {
if x < 1871 {
if x < 1872 {
if x < 1873 {
if x < 1874 {
if x < 1875 {
if x < 1876 {
if x < 1877 {
if x < 1878 {
if x < 1879 {
if x < 1880 {
if x < 1881 {
if x < 1882 {
if x < 1883 {
if x < 1884 {
if x < 1885 {
if x < 1886 {
if x < 1887 {
if x < 1888 {
if x < 1889 {
if x < 1890 {
if x < 1891 {
if x < 1892 {
if x < 1893 {
if x < 1894 {
if x < 1895 {
if x < 1896 {
if x < 1897 {
if x < 1898 {
if x < 1899 {
if x < 1900 {
if x < 1901 {
if x < 1902 {
if x < 1903 {
if x < 1904 {
if x < 1905 {
if x < 1906 {
if x < 1907 {
if x < 1908 {
if x < 1909 {
if x < 1910 {
if x < 1911 {
if x < 1912 {
if x < 1913 {
if x < 1914 {
if x < 1915 {
if x < 1916 {
if x < 1917 {
if x < 1918 {
if x < 1919 {
if x < 1920 {
if x < 1921 {
if x < 1922 {
if x < 1923 {
if x < 1924 {
if x < 1925 {
if x < 1926 {
if x < 1927 {
if x < 1928 {
if x < 1929 {
if x < 1930 {
if x < 1931 {
if x < 1932 {
if x < 1933 {
if x < 1934 {
if x < 1935 {
if x < 1936 {
if x < 1937 {
if x < 1938 {
if x < 1939 {
if x < 1940 {
if x < 1941 {
if x < 1942 {
if x < 1943 {
if x < 1944 {
if x < 1945 {
if x < 1946 {
if x < 1947 {
if x < 1948 {
if x < 1949 {
if x < 1950 {
if x < 1951 {
if x < 1952 {
if x < 1953 {
if x < 1954 {
if x < 1955 {
if x < 1956 {
if x < 1957 {
if x < 1958 {
if x < 1959 {
if x < 1960 {
if x < 1961 {
if x < 1962 {
if x < 1963 {
if x < 1964 {
if x < 1965 {
if x < 1966 {
if x < 1967 {
if x < 1968 {
if x < 1969 {
if x < 1970 {
if x < 1971 {
if x < 1972 {
if x < 1973 {
if x < 1974 {
if x < 1975 {
if x < 1976 {
if x < 1977 {
if x < 1978 {
if x < 1979 {
if x < 1980 {
if x < 1981 {
if x < 1982 {
if x < 1983 {
if x < 1984 {
if x < 1985 {
if x < 1986 {
if x < 1987 {
if x < 1988 {
if x < 1989 {
if x < 1990 {
if x < 1991 {
if x < 1992 {
if x < 1993 {
if x < 1994 {
if x < 1995 {
if x < 1996 {
if x < 1997 {
if x < 1998 {
if x < 1999 {
if x < 2000 {
if x < 2001 {
if x < 2002 {
if x < 2003 {
if x < 2004 {
if x < 2005 {
if x < 2006 {
if x < 2007 {
if x < 2008 {
if x < 2009 {
if x < 2010 {
if x < 2011 {
if x < 2012 {
if x < 2013 {
if x < 2014 {
if x < 2015 {
if x < 2016 {
if x < 2017 {
if x < 2018 {
if x < 2019 {
if x < 2020 {
if x < 2021 {
if x < 2022 {
if x < 2023 {
if x < 2024 {
if x < 2025 {
if x < 2026 {
if x < 2027 {
if x < 2028 {
if x < 2029 {
if x < 2030 {
if x < 2031 {
if x < 2032 {
if x < 2033 {
if x < 2034 {
if x < 2035 {
if x < 2036 {
if x < 2037 {
if x < 2038 {
if x < 2039 {
if x < 2040 {
if x < 2041 {
if x < 2042 {
if x < 2043 {
if x < 2044 {
if x < 2045 {
if x < 2046 {
if x < 2047 {
if x < 2048 {
if x < 2049 {
if x < 2050 {
if x < 2051 {
if x < 2052 {
if x < 2053 {
if x < 2054 {
if x < 2055 {
if x < 2056 {
if x < 2057 {
if x < 2058 {
if x < 2059 {
if x < 2060 {
if x < 2061 {
if x < 2062 {
if x < 2063 {
if x < 2064 {
if x < 2065 {
if x < 2066 {
if x < 2067 {
if x < 2068 {
if x < 2069 {
if x < 2070 {
if x < 2071 {
if x < 2072 {
if x < 2073 {
if x < 2074 {
if x < 2075 {
if x < 2076 {
if x < 2077 {
if x < 2078 {
if x < 2079 {
if x < 2080 {
if x < 2081 {
if x < 2082 {
if x < 2083 {
if x < 2084 {
if x < 2085 {
if x < 2086 {
if x < 2087 {
if x < 2088 {
if x < 2089 {
if x < 2090 {
if x < 2091 {
if x < 2092 {
if x < 2093 {
if x < 2094 {
if x < 2095 {
if x < 2096 {
if x < 2097 {
if x < 2098 {
if x < 2099 {
if x < 2100 {
if x < 2101 {
if x < 2102 {
if x < 2103 {
if x < 2104 {
if x < 2105 {
if x < 2106 {
if x < 2107 {
if x < 2108 {
if x < 2109 {
if x < 2110 {
if x < 2111 {
if x < 2112 {
if x < 2113 {
if x < 2114 {
if x < 2115 {
if x < 2116 {
if x < 2117 {
if x < 2118 {
if x < 2119 {
if x < 2120 {
if x < 2121 {
if x < 2122 {
if x < 2123 {
if x < 2124 {
if x < 2125 {
if x < 2126 {
if x < 2127 {
if x < 2128 {
if x < 2129 {
if x < 2130 {
if x < 2131 {
if x < 2132 {
if x < 2133 {
if x < 2134 {
if x < 2135 {
if x < 2136 {
if x < 2137 {
if x < 2138 {
if x < 2139 {
if x < 2140 {
if x < 2141 {
if x < 2142 {
if x < 2143 {
if x < 2144 {
if x < 2145 {
if x < 2146 {
if x < 2147 {
if x < 2148 {
if x < 2149 {
if x < 2150 {
if x < 2151 {
if x < 2152 {
if x < 2153 {
if x < 2154 {
if x < 2155 {
if x < 2156 {
if x < 2157 {
if x < 2158 {
if x < 2159 {
if x < 2160 {
if x < 2161 {
if x < 2162 {
if x < 2163 {
if x < 2164 {
if x < 2165 {
if x < 2166 {
if x < 2167 {
if x < 2168 {
if x < 2169 {
if x < 2170 {
if x < 2171 {
if x < 2172 {
if x < 2173 {
if x < 2174 {
if x < 2175 {
if x < 2176 {
if x < 2177 {
if x < 2178 {
if x < 2179 {
if x < 2180 {
if x < 2181 {
if x < 2182 {
if x < 2183 {
if x < 2184 {
if x < 2185 {
if x < 2186 {
if x < 2187 {
if x < 2188 {
if x < 2189 {
if x < 2190 {
if x < 2191 {
if x < 2192 {
if x < 2193 {
if x < 2194 {
if x < 2195 {
if x < 2196 {
if x < 2197 {
if x < 2198 {
if x < 2199 {
if x < 2200 {
if x < 2201 {
if x < 2202 {
if x < 2203 {
if x < 2204 {
if x < 2205 {
if x < 2206 {
if x < 2207 {
if x < 2208 {
if x < 2209 {
if x < 2210 {
if x < 2211 {
if x < 2212 {
if x < 2213 {
if x < 2214 {
if x < 2215 {
if x < 2216 {
if x < 2217 {
if x < 2218 {
if x < 2219 {
if x < 2220 {
if x < 2221 {
if x < 2222 {
if x < 2223 {
if x < 2224 {
if x < 2225 {
if x < 2226 {
if x < 2227 {
if x < 2228 {
if x < 2229 {
if x < 2230 {
if x < 2231 {
if x < 2232 {
if x < 2233 {
if x < 2234 {
if x < 2235 {
if x < 2236 {
if x < 2237 {
if x < 2238 {
if x < 2239 {
if x < 2240 {
if x < 2241 {
if x < 2242 {
if x < 2243 {
if x < 2244 {
if x < 2245 {
if x < 2246 {
if x < 2247 {
if x < 2248 {
if x < 2249 {
if x < 2250 {
if x < 2251 {
if x < 2252 {
if x < 2253 {
if x < 2254 {
if x < 2255 {
if x < 2256 {
if x < 2257 {
if x < 2258 {
if x < 2259 {
if x < 2260 {
if x < 2261 {
if x < 2262 {
if x < 2263 {
if x < 2264 {
if x < 2265 {
if x < 2266 {
if x < 2267 {
if x < 2268 {
if x < 2269 {
if x < 2270 {
if x < 2271 {
if x < 2272 {
if x < 2273 {
if x < 2274 {
if x < 2275 {
if x < 2276 {
if x < 2277 {
if x < 2278 {
if x < 2279 {
if x < 2280 {
if x < 2281 {
if x < 2282 {
if x < 2283 {
if x < 2284 {
if x < 2285 {
if x < 2286 {
if x < 2287 {
if x < 2288 {
if x < 2289 {
if x < 2290 {
if x < 2291 {
if x < 2292 {
if x < 2293 {
if x < 2294 {
if x < 2295 {
if x < 2296 {
if x < 2297 {
if x < 2298 {
if x < 2299 {
if x < 2300 {
if x < 2301 {
if x < 2302 {
if x < 2303 {
if x < 2304 {
if x < 2305 {
if x < 2306 {
if x < 2307 {
if x < 2308 {
if x < 2309 {
if x < 2310 {
if x < 2311 {
if x < 2312 {
if x < 2313 {
if x < 2314 {
if x < 2315 {
if x < 2316 {
if x < 2317 {
if x < 2318 {
if x < 2319 {
if x < 2320 {
if x < 2321 {
if x < 2322 {
if x < 2323 {
if x < 2324 {
if x < 2325 {
if x < 2326 {
if x < 2327 {
if x < 2328 {
if x < 2329 {
if x < 2330 {
if x < 2331 {
if x < 2332 {
if x < 2333 {
if x < 2334 {
if x < 2335 {
if x < 2336 {
if x < 2337 {
if x < 2338 {
if x < 2339 {
if x < 2340 {
if x < 2341 {
if x < 2342 {
if x < 2343 {
if x < 2344 {
if x < 2345 {
if x < 2346 {
if x < 2347 {
if x < 2348 {
if x < 2349 {
if x < 2350 {
if x < 2351 {
if x < 2352 {
if x < 2353 {
if x < 2354 {
if x < 2355 {
if x < 2356 {
if x < 2357 {
if x < 2358 {
if x < 2359 {
if x < 2360 {
if x < 2361 {
if x < 2362 {
if x < 2363 {
if x < 2364 {
if x < 2365 {
if x < 2366 {
if x < 2367 {
if x < 2368 {
if x < 2369 {
if x < 2370 {
if x < 2371 {
if x < 2372 {
if x < 2373 {
if x < 2374 {
if x < 2375 {
if x < 2376 {
if x < 2377 {
if x < 2378 {
if x < 2379 {
if x < 2380 {
if x < 2381 {
if x < 2382 {
if x < 2383 {
if x < 2384 {
if x < 2385 {
if x < 2386 {
if x < 2387 {
if x < 2388 {
if x < 2389 {
if x < 2390 {
if x < 2391 {
if x < 2392 {
if x < 2393 {
if x < 2394 {
if x < 2395 {
if x < 2396 {
if x < 2397 {
if x < 2398 {
if x < 2399 {
if x < 2400 {
if x < 2401 {
if x < 2402 {
if x < 2403 {
if x < 2404 {
if x < 2405 {
if x < 2406 {
if x < 2407 {
if x < 2408 {
if x < 2409 {
if x < 2410 {
if x < 2411 {
if x < 2412 {
if x < 2413 {
if x < 2414 {
if x < 2415 {
if x < 2416 {
if x < 2417 {
if x < 2418 {
if x < 2419 {
if x < 2420 {
if x < 2421 {
if x < 2422 {
if x < 2423 {
if x < 2424 {
if x < 2425 {
if x < 2426 {
if x < 2427 {
if x < 2428 {
if x < 2429 {
if x < 2430 {
if x < 2431 {
if x < 2432 {
if x < 2433 {
if x < 2434 {
if x < 2435 {
if x < 2436 {
if x < 2437 {
if x < 2438 {
if x < 2439 {
if x < 2440 {
if x < 2441 {
if x < 2442 {
if x < 2443 {
if x < 2444 {
if x < 2445 {
if x < 2446 {
if x < 2447 {
if x < 2448 {
if x < 2449 {
if x < 2450 {
if x < 2451 {
if x < 2452 {
if x < 2453 {
if x < 2454 {
if x < 2455 {
if x < 2456 {
if x < 2457 {
if x < 2458 {
if x < 2459 {
if x < 2460 {
if x < 2461 {
if x < 2462 {
if x < 2463 {
if x < 2464 {
if x < 2465 {
if x < 2466 {
if x < 2467 {
if x < 2468 {
if x < 2469 {
if x < 2470 {
if x < 2471 {
if x < 2472 {
if x < 2473 {
if x < 2474 {
if x < 2475 {
if x < 2476 {
if x < 2477 {
if x < 2478 {
if x < 2479 {
if x < 2480 {
if x < 2481 {
if x < 2482 {
if x < 2483 {
if x < 2484 {
if x < 2485 {
if x < 2486 {
if x < 2487 {
if x < 2488 {
if x < 2489 {
if x < 2490 {
if x < 2491 {
if x < 2492 {
if x < 2493 {
if x < 2494 {
if x < 2495 {
if x < 2496 {
if x < 2497 {
if x < 2498 {
if x < 2499 {
if x < 2500 {
if x < 2501 {
if x < 2502 {
if x < 2503 {
if x < 2504 {
if x < 2505 {
if x < 2506 {
if x < 2507 {
if x < 2508 {
if x < 2509 {
if x < 2510 {
if x < 2511 {
if x < 2512 {
if x < 2513 {
if x < 2514 {
if x < 2515 {
if x < 2516 {
if x < 2517 {
if x < 2518 {
if x < 2519 {
if x < 2520 {
if x < 2521 {
if x < 2522 {
if x < 2523 {
if x < 2524 {
if x < 2525 {
if x < 2526 {
if x < 2527 {
if x < 2528 {
if x < 2529 {
if x < 2530 {
if x < 2531 {
if x < 2532 {
if x < 2533 {
if x < 2534 {
if x < 2535 {
if x < 2536 {
if x < 2537 {
if x < 2538 {
if x < 2539 {
if x < 2540 {
if x < 2541 {
if x < 2542 {
if x < 2543 {
if x < 2544 {
if x < 2545 {
if x < 2546 {
if x < 2547 {
if x < 2548 {
if x < 2549 {
if x < 2550 {
if x < 2551 {
if x < 2552 {
if x < 2553 {
if x < 2554 {
if x < 2555 {
if x < 2556 {
if x < 2557 {
if x < 2558 {
if x < 2559 {
if x < 2560 {
if x < 2561 {
if x < 2562 {
if x < 2563 {
if x < 2564 {
if x < 2565 {
if x < 2566 {
if x < 2567 {
if x < 2568 {
if x < 2569 {
if x < 2570 {
if x < 2571 {
if x < 2572 {
if x < 2573 {
if x < 2574 {
if x < 2575 {
if x < 2576 {
if x < 2577 {
if x < 2578 {
if x < 2579 {
if x < 2580 {
if x < 2581 {
if x < 2582 {
if x < 2583 {
if x < 2584 {
if x < 2585 {
if x < 2586 {
if x < 2587 {
if x < 2588 {
if x < 2589 {
if x < 2590 {
if x < 2591 {
if x < 2592 {
if x < 2593 {
if x < 2594 {
if x < 2595 {
if x < 2596 {
if x < 2597 {
if x < 2598 {
if x < 2599 {
if x < 2600 {
if x < 2601 {
if x < 2602 {
if x < 2603 {
if x < 2604 {
if x < 2605 {
if x < 2606 {
if x < 2607 {
if x < 2608 {
if x < 2609 {
if x < 2610 {
if x < 2611 {
if x < 2612 {
if x < 2613 {
if x < 2614 {
if x < 2615 {
if x < 2616 {
if x < 2617 {
if x < 2618 {
if x < 2619 {
if x < 2620 {
if x < 2621 {
if x < 2622 {
if x < 2623 {
if x < 2624 {
if x < 2625 {
if x < 2626 {
if x < 2627 {
if x < 2628 {
if x < 2629 {
if x < 2630 {
if x < 2631 {
if x < 2632 {
if x < 2633 {
if x < 2634 {
if x < 2635 {
if x < 2636 {
if x < 2637 {
if x < 2638 {
if x < 2639 {
if x < 2640 {
if x < 2641 {
if x < 2642 {
if x < 2643 {
if x < 2644 {
if x < 2645 {
if x < 2646 {
if x < 2647 {
if x < 2648 {
if x < 2649 {
if x < 2650 {
if x < 2651 {
if x < 2652 {
if x < 2653 {
if x < 2654 {
if x < 2655 {
if x < 2656 {
if x < 2657 {
if x < 2658 {
if x < 2659 {
if x < 2660 {
if x < 2661 {
if x < 2662 {
if x < 2663 {
if x < 2664 {
if x < 2665 {
if x < 2666 {
if x < 2667 {
if x < 2668 {
if x < 2669 {
if x < 2670 {
if x < 2671 {
if x < 2672 {
if x < 2673 {
if x < 2674 {
if x < 2675 {
if x < 2676 {
if x < 2677 {
if x < 2678 {
if x < 2679 {
if x < 2680 {
if x < 2681 {
if x < 2682 {
if x < 2683 {
if x < 2684 {
if x < 2685 {
if x < 2686 {
if x < 2687 {
if x < 2688 {
if x < 2689 {
if x < 2690 {
if x < 2691 {
if x < 2692 {
if x < 2693 {
if x < 2694 {
if x < 2695 {
if x < 2696 {
if x < 2697 {
if x < 2698 {
if x < 2699 {
if x < 2700 {
if x < 2701 {
if x < 2702 {
if x < 2703 {
if x < 2704 {
if x < 2705 {
if x < 2706 {
if x < 2707 {
if x < 2708 {
if x < 2709 {
if x < 2710 {
if x < 2711 {
if x < 2712 {
if x < 2713 {
if x < 2714 {
if x < 2715 {
if x < 2716 {
if x < 2717 {
if x < 2718 {
if x < 2719 {
if x < 2720 {
if x < 2721 {
if x < 2722 {
if x < 2723 {
if x < 2724 {
if x < 2725 {
if x < 2726 {
if x < 2727 {
if x < 2728 {
if x < 2729 {
if x < 2730 {
if x < 2731 {
if x < 2732 {
if x < 2733 {
if x < 2734 {
if x < 2735 {
if x < 2736 {
if x < 2737 {
if x < 2738 {
if x < 2739 {
if x < 2740 {
if x < 2741 {
if x < 2742 {
if x < 2743 {
if x < 2744 {
if x < 2745 {
if x < 2746 {
if x < 2747 {
if x < 2748 {
if x < 2749 {
if x < 2750 {
if x < 2751 {
if x < 2752 {
if x < 2753 {
if x < 2754 {
if x < 2755 {
if x < 2756 {
if x < 2757 {
if x < 2758 {
if x < 2759 {
if x < 2760 {
if x < 2761 {
if x < 2762 {
if x < 2763 {
if x < 2764 {
if x < 2765 {
if x < 2766 {
if x < 2767 {
if x < 2768 {
if x < 2769 {
if x < 2770 {
if x < 2771 {
if x < 2772 {
if x < 2773 {
if x < 2774 {
if x < 2775 {
if x < 2776 {
if x < 2777 {
if x < 2778 {
if x < 2779 {
if x < 2780 {
if x < 2781 {
if x < 2782 {
if x < 2783 {
if x < 2784 {
if x < 2785 {
if x < 2786 {
if x < 2787 {
if x < 2788 {
if x < 2789 {
if x < 2790 {
if x < 2791 {
if x < 2792 {
if x < 2793 {
if x < 2794 {
if x < 2795 {
if x < 2796 {
if x < 2797 {
if x < 2798 {
if x < 2799 {
if x < 2800 {
if x < 2801 {
if x < 2802 {
if x < 2803 {
if x < 2804 {
if x < 2805 {
if x < 2806 {
if x < 2807 {
if x < 2808 {
if x < 2809 {
if x < 2810 {
if x < 2811 {
if x < 2812 {
if x < 2813 {
if x < 2814 {
if x < 2815 {
if x < 2816 {
if x < 2817 {
if x < 2818 {
if x < 2819 {
if x < 2820 {
if x < 2821 {
if x < 2822 {
if x < 2823 {
if x < 2824 {
if x < 2825 {
if x < 2826 {
if x < 2827 {
if x < 2828 {
if x < 2829 {
if x < 2830 {
if x < 2831 {
if x < 2832 {
if x < 2833 {
if x < 2834 {
if x < 2835 {
if x < 2836 {
if x < 2837 {
if x < 2838 {
if x < 2839 {
if x < 2840 {
if x < 2841 {
if x < 2842 {
if x < 2843 {
if x < 2844 {
if x < 2845 {
if x < 2846 {
if x < 2847 {
if x < 2848 {
if x < 2849 {
if x < 2850 {
if x < 2851 {
if x < 2852 {
if x < 2853 {
if x < 2854 {
if x < 2855 {
if x < 2856 {
if x < 2857 {
if x < 2858 {
if x < 2859 {
if x < 2860 {
if x < 2861 {
if x < 2862 {
if x < 2863 {
if x < 2864 {
if x < 2865 {
if x < 2866 {
if x < 2867 {
if x < 2868 {
if x < 2869 {
if x < 2870 {
if x < 2871 {
if x < 2872 {
if x < 2873 {
if x < 2874 {
if x < 2875 {
if x < 2876 {
if x < 2877 {
if x < 2878 {
if x < 2879 {
if x < 2880 {
if x < 2881 {
if x < 2882 {
if x < 2883 {
if x < 2884 {
if x < 2885 {
if x < 2886 {
if x < 2887 {
if x < 2888 {
if x < 2889 {
if x < 2890 {
if x < 2891 {
if x < 2892 {
if x < 2893 {
if x < 2894 {
if x < 2895 {
if x < 2896 {
if x < 2897 {
if x < 2898 {
if x < 2899 {
if x < 2900 {
if x < 2901 {
if x < 2902 {
if x < 2903 {
if x < 2904 {
if x < 2905 {
if x < 2906 {
if x < 2907 {
if x < 2908 {
if x < 2909 {
if x < 2910 {
if x < 2911 {
if x < 2912 {
if x < 2913 {
if x < 2914 {
if x < 2915 {
if x < 2916 {
if x < 2917 {
if x < 2918 {
if x < 2919 {
if x < 2920 {
if x < 2921 {
if x < 2922 {
if x < 2923 {
if x < 2924 {
if x < 2925 {
if x < 2926 {
if x < 2927 {
if x < 2928 {
if x < 2929 {
if x < 2930 {
if x < 2931 {
if x < 2932 {
if x < 2933 {
if x < 2934 {
if x < 2935 {
if x < 2936 {
if x < 2937 {
if x < 2938 {
if x < 2939 {
if x < 2940 {
if x < 2941 {
if x < 2942 {
if x < 2943 {
if x < 2944 {
if x < 2945 {
if x < 2946 {
if x < 2947 {
if x < 2948 {
if x < 2949 {
if x < 2950 {
if x < 2951 {
if x < 2952 {
if x < 2953 {
if x < 2954 {
if x < 2955 {
if x < 2956 {
if x < 2957 {
if x < 2958 {
if x < 2959 {
if x < 2960 {
if x < 2961 {
if x < 2962 {
if x < 2963 {
if x < 2964 {
if x < 2965 {
if x < 2966 {
if x < 2967 {
if x < 2968 {
if x < 2969 {
if x < 2970 {
if x < 2971 {
if x < 2972 {
if x < 2973 {
if x < 2974 {
if x < 2975 {
if x < 2976 {
if x < 2977 {
if x < 2978 {
if x < 2979 {
if x < 2980 {
if x < 2981 {
if x < 2982 {
if x < 2983 {
if x < 2984 {
if x < 2985 {
if x < 2986 {
if x < 2987 {
if x < 2988 {
if x < 2989 {
if x < 2990 {
if x < 2991 {
if x < 2992 {
if x < 2993 {
if x < 2994 {
if x < 2995 {
if x < 2996 {
if x < 2997 {
if x < 2998 {
if x < 2999 {
if x < 3000 {
    println!("deep {}", x);
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
}
