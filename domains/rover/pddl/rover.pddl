; domains/rover/rover.ixt in PDDL 2.1 (durative actions, numeric fluents) with PDDL 2.2's timed initial
; literals, for running other planners on the problems of `mavtempo bench suite --write DIR --pddl`.
; Where the .ixt leaves a number open, this file takes the worst case (src/planner/suite/pddl.rs):
; - every duration is the longest the .ixt allows: a move takes distance / 0.3 m/s (the slowest speed),
;   move_ptu 5 s, take_picture 20 s, download_images 40 s, communicate 60 s, a recharge its full 600 s;
; - a picture takes 1 storage slot (sizes 0.9 to 1), a download frees 2 (2 to 2.4): as the .ixt's worst
;   cases, but fixed, where the native planner must hold both ends of each range at once;
; - a move costs 0.5 % of battery per metre; a recharge gives 0.0833 %/s x 600 s = 49.98 % and, as the
;   battery's capacity is 100, starts only at 50.02 % or less (the .ixt can also recharge for 60 to 600 s).
; The problem gives travel-time and travel-energy for each ordered pair of distinct locations (path).
(define (domain rover)
  (:requirements :typing :durative-actions :fluents :timed-initial-literals)
  (:types location station ptu-position)
  (:constants forward down - ptu-position)
  (:predicates
    (robot-at ?l - location)                 ; AT_ROBOT, none while moving
    (still)                                  ; ROBOT_STATUS = STILL
    (ptu-at ?p - ptu-position)               ; PTU_POS, none while the PTU turns
    (ptu-turn ?from - ptu-position ?to - ptu-position)   ; static: ?from != ?to
    (path ?from - location ?to - location)   ; static: ?from != ?to
    (mvt-init-f) (mvt-idle-init) (mvt-init)  ; MVT_INIT = F, IDLE_INIT, T
    (ptu-init-f) (ptu-idle-init) (ptu-init)  ; PTU_INIT = F, IDLE_INIT, T
    (picture ?l - location)
    (visible ?w - station)                   ; VISIBLE = ?w: timed initial literals
    (communicated ?w - station)
    (camera-free) (antenna-free) (panels-free)   ; the unary resources
    (before-deadline-picture ?l - location)  ; deleted at the picture goal's deadline
    (before-deadline-comm ?w - station)      ; deleted at the communication goal's deadline
    (before-horizon))                        ; deleted at the horizon
  (:functions
    (travel-time ?from - location ?to - location)
    (travel-energy ?from - location ?to - location)
    (storage)                                ; free image slots, capacity 3
    (battery))                               ; percent, capacity 100

  (:durative-action move
    :parameters (?from - location ?to - location)
    :duration (= ?duration (travel-time ?from ?to))
    :condition (and (at start (path ?from ?to)) (at start (robot-at ?from)) (at start (still))
                    (at start (ptu-at forward)) (over all (ptu-at forward))
                    (at start (mvt-init)) (over all (mvt-init)) (at start (camera-free))
                    (at start (>= (battery) (travel-energy ?from ?to))) (at end (before-horizon)))
    :effect (and (at start (not (robot-at ?from))) (at start (not (still))) (at start (not (camera-free)))
                 (at start (decrease (battery) (travel-energy ?from ?to)))
                 (at end (robot-at ?to)) (at end (still)) (at end (camera-free))))

  (:durative-action move_ptu
    :parameters (?from - ptu-position ?to - ptu-position)
    :duration (= ?duration 5)
    :condition (and (at start (ptu-turn ?from ?to)) (at start (ptu-at ?from))
                    (at start (ptu-init)) (over all (ptu-init)) (at start (still)) (over all (still))
                    (at end (before-horizon)))
    :effect (and (at start (not (ptu-at ?from))) (at end (ptu-at ?to))))

  (:durative-action take_picture
    :parameters (?l - location)
    :duration (= ?duration 20)
    :condition (and (at start (robot-at ?l)) (over all (robot-at ?l)) (at start (ptu-at down))
                    (over all (ptu-at down)) (at start (still)) (over all (still)) (at start (camera-free))
                    (at start (>= (storage) 1)) (at end (before-deadline-picture ?l))
                    (at end (before-horizon)))
    :effect (and (at start (not (camera-free))) (at start (decrease (storage) 1))
                 (at end (picture ?l)) (at end (camera-free))))

  (:durative-action download_images
    :parameters (?w - station)
    :duration (= ?duration 40)
    :condition (and (at start (visible ?w)) (over all (visible ?w)) (at start (antenna-free))
                    (at end (<= (storage) 1)) (at end (before-horizon)))
    :effect (and (at start (not (antenna-free))) (at end (increase (storage) 2)) (at end (antenna-free))))

  (:durative-action communicate
    :parameters (?w - station)
    :duration (= ?duration 60)
    :condition (and (at start (visible ?w)) (over all (visible ?w)) (at start (antenna-free))
                    (at end (before-deadline-comm ?w)) (at end (before-horizon)))
    :effect (and (at start (not (antenna-free))) (at end (communicated ?w)) (at end (antenna-free))))

  (:durative-action recharge_battery
    :parameters ()
    :duration (= ?duration 600)
    :condition (and (at start (still)) (over all (still)) (at start (panels-free))
                    (at start (<= (battery) 50.02)) (at end (before-horizon)))
    :effect (and (at start (not (panels-free))) (at end (increase (battery) 49.98)) (at end (panels-free))))

  (:durative-action init_mvt_generation
    :parameters ()
    :duration (= ?duration 60)
    :condition (and (at start (still)) (over all (still)) (at start (camera-free)) (at start (mvt-init-f))
                    (at end (before-horizon)))
    :effect (and (at start (not (camera-free))) (at start (not (mvt-init-f))) (at start (mvt-idle-init))
                 (at end (not (mvt-idle-init))) (at end (mvt-init)) (at end (camera-free))))

  (:durative-action platine_init
    :parameters ()
    :duration (= ?duration 30)
    :condition (and (at start (still)) (over all (still)) (at start (ptu-init-f)) (at end (before-horizon)))
    :effect (and (at start (not (ptu-init-f))) (at start (ptu-idle-init))
                 (at end (not (ptu-idle-init))) (at end (ptu-init)))))
