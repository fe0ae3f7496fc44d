; domains/auv/auv.ixt in PDDL 2.1 (durative actions, numeric fluents) with PDDL 2.2's timed initial
; literals, for running other planners on the problems of `mavtempo bench suite --write DIR --pddl`.
; Durations are the longest the .ixt allows (src/planner/suite/pddl.rs): a leg takes distance / 1.0 m/s
; (the slowest speed), given by the problem as travel-time; survey and sample 10 min each.
(define (domain auv)
  (:requirements :typing :durative-actions :fluents :timed-initial-literals)
  (:types location)
  (:predicates
    (auv-at ?l - location)                   ; AUV_AT, none while travelling
    (connected ?from - location ?to - location)   ; static
    (surveyed ?l - location)
    (sampled ?l - location)
    (before-horizon))                        ; deleted at the horizon
  (:functions (travel-time ?from - location ?to - location))

  (:durative-action go
    :parameters (?from - location ?to - location)
    :duration (= ?duration (travel-time ?from ?to))
    :condition (and (at start (connected ?from ?to)) (at start (auv-at ?from)) (at end (before-horizon)))
    :effect (and (at start (not (auv-at ?from))) (at end (auv-at ?to))))

  (:durative-action survey
    :parameters (?l - location)
    :duration (= ?duration 600)
    :condition (and (at start (auv-at ?l)) (over all (auv-at ?l)) (at end (before-horizon)))
    :effect (at end (surveyed ?l)))

  (:durative-action sample
    :parameters (?l - location)
    :duration (= ?duration 600)
    :condition (and (at start (auv-at ?l)) (over all (auv-at ?l)) (at start (surveyed ?l))
                    (over all (surveyed ?l)) (at end (before-horizon)))
    :effect (at end (sampled ?l))))
